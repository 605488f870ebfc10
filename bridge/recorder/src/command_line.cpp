#include "retreat/recorder/command_line.hpp"

#include "retreat/scenario/program_options.hpp"
#include "retreat/wire/topics.hpp"

namespace retreat::recorder {

std::variant<RecordCommandLine, int> parse_command_line(int argc, char** argv) {
  constexpr const char* program = "retreat-record";
  CLI::App app{"retreat-record: records a swarm's DDS traffic (every topic, CDR bytes as on the "
               "wire) into an MCAP file"};
  scenario::CommonOptions common;
  RecordCommandLine out;
  scenario::add_common_options(app, common);
  app.add_option("--out", out.out, "the MCAP file to write (created or truncated)")->required();
  if (const auto code = scenario::parse_command_line(app, argc, argv, program)) return *code;
  return scenario::guarded(program, [&]() -> std::variant<RecordCommandLine, int> {
    out.scenario = scenario::load_scenario(common);
    out.print_config = common.print_config;
    if (out.scenario.dds.vendor == scenario::Vendor::inmemory) {
      throw scenario::ConfigError("dds.vendor = inmemory: a recorder reads DDS traffic (fastdds or cyclonedds)");
    }
    // The participant's options, checked now (a secure swarm's PKI must hold the `recorder`
    // identity): a refused start writes no file.
    (void)scenario::participant_options(out.scenario, program, wire::recorder_user_data, "recorder");
    return out;
  });
}

}  // namespace retreat::recorder

// Cross-vendor interoperation on the wire: a writer process of one vendor and a reader process
// of another exchange 1,000 samples of every message kind; the reader checks every field.

#include <gtest/gtest.h>

#include <filesystem>

#include "retreat/testing/domains.hpp"
#include "retreat/testing/process.hpp"
#include "retreat/transport/factory.hpp"

namespace {

using namespace std::chrono_literals;
using retreat::testing::ChildProcess;

struct Pair {
  const char* writer;
  const char* reader;
};

void exchange(const Pair& pair, int domain) {
  const auto vendors = retreat::transport::dds_vendors();
  for (const char* v : {pair.writer, pair.reader}) {
    if (std::find(vendors.begin(), vendors.end(), v) == vendors.end()) {
      GTEST_SKIP() << v << " is not built (RETREAT_WITH_... off)";
    }
  }
  const std::string dir = ::testing::TempDir();
  const std::string tag = std::string(pair.writer) + "_to_" + pair.reader;
  // The writer starts writing once the reader says it has matched (the --ready file).
  const std::string ready = dir + "/probe_ready_" + tag;
  std::filesystem::remove(ready);
  ChildProcess reader({RETREAT_WIRE_PROBE, "--role", "reader", "--dds", pair.reader, "--domain",
                       std::to_string(domain), "--count", "1000", "--ready", ready, "--prefix", "probe_" + tag},
                      dir + "/probe_reader_" + tag + ".log");
  ChildProcess writer({RETREAT_WIRE_PROBE, "--role", "writer", "--dds", pair.writer, "--domain",
                       std::to_string(domain), "--count", "1000", "--ready", ready, "--prefix", "probe_" + tag},
                      dir + "/probe_writer_" + tag + ".log");
  const auto reader_code = reader.wait_for(retreat::testing::hang_ceiling);
  const auto writer_code = writer.wait_for(retreat::testing::hang_ceiling);
  ASSERT_TRUE(reader_code.has_value()) << "reader did not finish";
  EXPECT_EQ(*reader_code, 0) << retreat::testing::read_file(dir + "/probe_reader_" + tag + ".log");
  ASSERT_TRUE(writer_code.has_value()) << "writer did not finish";
  EXPECT_EQ(*writer_code, 0) << retreat::testing::read_file(dir + "/probe_writer_" + tag + ".log");
}

TEST(CrossVendor, FastDdsWriterToCycloneReaderDeliversEveryKindIdentically) {
  exchange({"fastdds", "cyclonedds"}, retreat::testing::domains::cross_vendor.at(0));
}

TEST(CrossVendor, CycloneWriterToFastDdsReaderDeliversEveryKindIdentically) {
  exchange({"cyclonedds", "fastdds"}, retreat::testing::domains::cross_vendor.at(1));
}

}  // namespace

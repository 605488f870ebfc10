// Lists what retreat's MCAP reader reads from a file, in the form write_mcap.mjs prints what the
// reference writer wrote: messages in file order, then the metadata, then the channels. Exit 2
// with the reader's one line if the file cannot be read.
//
//   retreat_mcap_list FILE

#include <cstdio>
#include <iostream>
#include <sstream>

#include "retreat/recording/mcap_reader.hpp"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: retreat_mcap_list FILE\n";
    return 2;
  }
  using namespace retreat::recording;
  std::ostringstream messages;
  try {
    const auto contents = read_mcap_file(argv[1], [&](const McapChannel& c, const McapMessage& m) {
      messages << "message " << c.topic << ' ' << m.sequence << ' ' << m.log_time << ' ' << m.publish_time << ' ';
      for (const auto b : m.data) {
        char hex[3];
        std::snprintf(hex, sizeof hex, "%02x", std::to_integer<unsigned>(b));
        messages << hex;
      }
      messages << '\n';
    });
    std::cout << messages.str();
    for (const auto& [name, map] : contents.metadata) {
      std::cout << "metadata " << name;
      for (const auto& [k, v] : map) std::cout << ' ' << k << '=' << v;
      std::cout << '\n';
    }
    for (const auto& [id, c] : contents.channels) {
      std::cout << "channel " << c.topic << ' ';
      if (c.schema_id == 0) {
        std::cout << "- -";
      } else {
        const auto& s = contents.schemas.at(c.schema_id);
        std::cout << s.name << ' ' << s.encoding;
      }
      std::cout << ' ' << c.message_encoding;
      for (const auto& [k, v] : c.metadata) std::cout << ' ' << k << '=' << v;
      std::cout << '\n';
    }
    if (!contents.complete) {
      std::cerr << "retreat_mcap_list: the file has no footer\n";
      return 1;
    }
  } catch (const McapError& e) {
    std::cerr << "retreat_mcap_list: " << e.what() << '\n';
    return 2;
  }
  return 0;
}

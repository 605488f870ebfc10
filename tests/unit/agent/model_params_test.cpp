#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "retreat/model/format_number.hpp"
#include "retreat/model/params.hpp"

namespace retreat::model {
namespace {

/// The message of the invalid_argument thrown by p.validate() ("" if none).
std::string validation_message(const ModelParams& p) {
  try {
    p.validate();
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  return "";
}

TEST(ModelParams, DefaultsAreTheRobotariumExperimentAndValid) {
  const ModelParams p;
  EXPECT_EQ(p.lambda_p, 1.32);
  EXPECT_EQ(p.lambda_d, 1.32);
  EXPECT_EQ(p.C, 0.03);
  EXPECT_EQ(p.delta, 0.1);
  EXPECT_EQ(p.v, 0.1);
  EXPECT_EQ(p.rho, 2.44);
  EXPECT_NO_THROW(p.validate());
}

TEST(ModelParams, RejectsANegativeDeltaWithAOneLineMessage) {
  ModelParams p;
  p.delta = -0.1;
  EXPECT_EQ(validation_message(p), "model.delta = -0.1: must be > 0 (m)");
}

TEST(ModelParams, NamesTheFieldAndTheValueOfEveryOutOfRangeField) {
  const double bad_values[] = {0.0, -2.5, std::numeric_limits<double>::quiet_NaN(),
                               std::numeric_limits<double>::infinity()};
  struct Field {
    const char* name;
    double ModelParams::*member;
  };
  const Field fields[] = {{"lambda_p", &ModelParams::lambda_p},
                          {"lambda_d", &ModelParams::lambda_d},
                          {"C", &ModelParams::C},
                          {"delta", &ModelParams::delta},
                          {"v", &ModelParams::v},
                          {"rho", &ModelParams::rho}};
  for (const Field& field : fields) {
    for (const double bad : bad_values) {
      ModelParams p;
      p.*field.member = bad;
      const std::string message = validation_message(p);
      const std::string expected_start =
          std::string("model.") + field.name + " = " + format_number(bad) + ": must be ";
      EXPECT_EQ(message.rfind(expected_start, 0), 0u) << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
  }
}

TEST(FormatNumber, WritesTheShortestTextThatReadsBackExactly) {
  EXPECT_EQ(format_number(0.1), "0.1");
  EXPECT_EQ(format_number(-3.0), "-3");
  EXPECT_EQ(format_number(90.0), "90");
  EXPECT_EQ(format_number(1.32), "1.32");
  EXPECT_EQ(format_number(std::numeric_limits<double>::quiet_NaN()), "nan");
  EXPECT_EQ(format_number(-std::numeric_limits<double>::infinity()), "-inf");
}

}  // namespace
}  // namespace retreat::model

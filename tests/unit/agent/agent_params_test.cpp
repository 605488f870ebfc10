#include "retreat/agent/agent_params.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <stdexcept>
#include <string>

#include "retreat/agent/retreat_agent.hpp"
#include "retreat/model/format_number.hpp"

namespace retreat::agent {
namespace {

/// The message of the invalid_argument thrown by p.validate() ("" if none).
std::string validation_message(const AgentParams& p) {
  try {
    p.validate();
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  return "";
}

const double nan = std::numeric_limits<double>::quiet_NaN();
const double inf = std::numeric_limits<double>::infinity();

TEST(AgentParams, DefaultsAreTheRobotariumExperimentAndValid) {
  const AgentParams p;
  EXPECT_EQ(p.L, 90.0);
  EXPECT_EQ(p.dt, 0.03);
  EXPECT_EQ(p.K_p, 0.03);
  EXPECT_EQ(p.lambda_in, 0.02);
  EXPECT_EQ(p.controller, "paper");
  EXPECT_NO_THROW(p.validate());
}

TEST(AgentParams, RejectsADecisionPeriodLongerThanTheWindow) {
  AgentParams p;
  p.dt = 100.0;
  EXPECT_EQ(validation_message(p), "agent.dt = 100: must be > 0 and <= agent.L (90) (s)");
}

TEST(AgentParams, RejectsAnUnknownControllerListingTheValidNames) {
  AgentParams p;
  p.controller = "foo";
  EXPECT_EQ(validation_message(p), "agent.controller = 'foo': must be one of paper, confident, "
                                  "influx-aware, confident-influx-aware, confident-proportional, "
                                  "influx-matching, adaptive-proportional");
}

TEST(AgentParams, NamesTheFieldAndTheValueOfEveryOutOfRangeNumber) {
  struct Case {
    const char* field;
    double AgentParams::*member;
    double value;
  };
  const Case cases[] = {{"L", &AgentParams::L, 0.0},
                        {"L", &AgentParams::L, -3.0},
                        {"L", &AgentParams::L, nan},
                        {"L", &AgentParams::L, inf},
                        {"dt", &AgentParams::dt, 0.0},
                        {"dt", &AgentParams::dt, -0.03},
                        {"dt", &AgentParams::dt, nan},
                        {"dt", &AgentParams::dt, 90.5},
                        {"K_p", &AgentParams::K_p, -0.01},
                        {"K_p", &AgentParams::K_p, nan},
                        {"K_p", &AgentParams::K_p, inf},
                        {"lambda_in", &AgentParams::lambda_in, -1.0},
                        {"lambda_in", &AgentParams::lambda_in, nan},
                        {"missed_onsets", &AgentParams::missed_onsets, 1.0},
                        {"missed_onsets", &AgentParams::missed_onsets, -0.1},
                        {"missed_onsets", &AgentParams::missed_onsets, nan},
                        {"false_onsets", &AgentParams::false_onsets, -0.5},
                        {"false_onsets", &AgentParams::false_onsets, inf}};
  for (const Case& c : cases) {
    AgentParams p;
    p.*c.member = c.value;
    const std::string message = validation_message(p);
    const std::string expected_start =
        std::string("agent.") + c.field + " = " + model::format_number(c.value) + ": must be ";
    EXPECT_EQ(message.rfind(expected_start, 0), 0u) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

TEST(AgentParams, AcceptsZeroGainAndZeroInfluxAndDtEqualToL) {
  AgentParams p;
  p.K_p = 0.0;
  p.lambda_in = 0.0;
  p.dt = p.L;
  EXPECT_NO_THROW(p.validate());
}

TEST(RetreatAgent, RefusesOutOfRangeParametersAtConstruction) {
  model::ModelParams bad_model;
  bad_model.v = -1.0;
  EXPECT_THROW(RetreatAgent(0, bad_model), std::invalid_argument);
  AgentParams bad_agent;
  bad_agent.L = -3.0;
  EXPECT_THROW(RetreatAgent(0, {}, bad_agent), std::invalid_argument);
}

}  // namespace
}  // namespace retreat::agent

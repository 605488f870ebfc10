#include "retreat/agent/controller_registry.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "retreat/agent/paper_controller.hpp"
#include "retreat/model/control.hpp"
#include "retreat/model/optimum.hpp"

namespace retreat::agent {
namespace {

TEST(ControllerRegistry, ListsThePaperControllerFirst) {
  const std::vector<std::string> names = controller_names();
  ASSERT_FALSE(names.empty());
  EXPECT_EQ(names.front(), "paper");
  EXPECT_TRUE(is_controller_name("paper"));
  EXPECT_FALSE(is_controller_name("Paper"));
}

TEST(ControllerRegistry, MakesEveryRegisteredControllerUnderItsName) {
  for (const std::string& name : controller_names()) {
    const auto controller = make_controller(name);
    ASSERT_NE(controller, nullptr);
    EXPECT_EQ(controller->name(), name);
  }
}

TEST(ControllerRegistry, RejectsAnUnknownNameListingTheValidOnes) {
  try {
    make_controller("foo");
    FAIL() << "no exception";
  } catch (const std::invalid_argument& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("'foo'"), std::string::npos) << message;
    for (const std::string& name : controller_names()) {
      EXPECT_NE(message.find(name), std::string::npos) << message;
    }
  }
}

TEST(PaperController, ReturnsEpsilonOfTheEstimateTimesDt) {
  const model::ModelParams model;
  const AgentParams agent;
  const OnsetWindow window(agent.L);
  PaperController controller;
  const double lambda_star = model::lambda_star(model);
  for (const double lambda_hat : {0.0, 1.0, lambda_star, 1.6, 3.0, 100.0}) {
    const ControllerInput input{90.0, 90.0, 0, agent.L, agent.dt, lambda_hat, lambda_star, model, agent, window};
    EXPECT_EQ(controller.retreat_probability(input),
              model::epsilon(lambda_hat, lambda_star, agent.lambda_in, agent.K_p) * agent.dt);
  }
}

}  // namespace
}  // namespace retreat::agent

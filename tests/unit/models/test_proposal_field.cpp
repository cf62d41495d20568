// The proposal's annealing schedule (src/models/fast/proposal_field.h: proposalAnneal): from an
// even spread at the first step to the proposal's weights after proposalAnnealSteps, rising fast
// (nerfacto's bias of 10: past half way by a tenth of the steps), and the weights in full without it.
#include <gtest/gtest.h>

#include "models/fast/proposal_field.h"

using namespace vknerf;

TEST(ProposalAnneal, RisesFromEvenToTheWeights) {
  FastModel m;
  m.proposalAnnealSteps = 1000;
  EXPECT_EQ(models::proposalAnneal(m, 0), 0.0f);
  EXPECT_NEAR(models::proposalAnneal(m, 100), 1.0 / 1.9, 1e-6);  // 10 x / (9 x + 1) at x = 0.1
  float last = 0.0f;
  for (uint32_t step = 1; step <= 1000; ++step) {
    const float a = models::proposalAnneal(m, step);
    EXPECT_GE(a, last) << step;
    last = a;
  }
  EXPECT_EQ(models::proposalAnneal(m, 1000), 1.0f);
  EXPECT_EQ(models::proposalAnneal(m, 5000), 1.0f);
  m.proposalAnnealSteps = 0;
  EXPECT_EQ(models::proposalAnneal(m, 0), 1.0f);
}

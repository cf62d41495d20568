// The vknerf command line: exit codes (0 ok, 1 runtime error, 2 usage error) and one-line errors
// that name the file or field.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "support/cli_run.h"
#include "vknerf/config.h"
#include "vknerf/trainer.h"

using vknerf::test::runCli;
using vknerf::test::scene;
using vknerf::test::shellWaitUntil;
using vknerf::test::temp;

TEST(Cli, HelpAndUsageErrors) {
  EXPECT_EQ(runCli("--help").code, 0);
  EXPECT_EQ(runCli("train --help").code, 0);
  EXPECT_EQ(runCli("").code, 2);
  EXPECT_EQ(runCli("no-such-command").code, 2);
  EXPECT_EQ(runCli("train " + scene() + " -o x.vknerf --no-such-flag").code, 2);
  EXPECT_EQ(runCli("train " + scene() + " -o x --steps -3").code, 2);          // not a count
  EXPECT_EQ(runCli("train " + scene() + " -o x --time 0").code, 2);            // not positive
  EXPECT_EQ(runCli("train " + scene() + " -o x --downscale 0").code, 2);
}

TEST(Cli, MissingSceneNamesThePath) {
  const vknerf::test::TempDir tmp("cli");
  auto r = runCli("train /no/such/scene -o " + tmp.file("y.vknerf") + " --steps 1");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.output.find("/no/such/scene"), std::string::npos) << r.output;
}

TEST(Cli, CorruptCheckpointIsAClearError) {
  const vknerf::test::TempDir tmp("cli");
  auto path = tmp.file("corrupt.vknerf");
  std::ofstream(path) << "definitely not a checkpoint";
  auto r = runCli("eval " + path + " " + scene());
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.output.find(path), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("error"), std::string::npos) << r.output;
}

TEST(Cli, UnknownDeviceIsARuntimeError) {
  auto r = runCli("--device no-such-gpu info");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.output.find("no-such-gpu"), std::string::npos) << r.output;
}

// SIGINT or SIGTERM once training has logged a step: it stops at a step boundary, saves, exits
// 128 + signal. A tiny vanilla model (--coarse/--fine are vanilla's flags): small steps, so one ends
// soon after the signal.
void interruptSavesALoadableCheckpoint(const std::string& signal, int expectedCode) {
  auto model = temp("interrupted_" + signal + ".vknerf"), out = temp("interrupted_render_" + signal);
  const std::string log = temp("interrupted_" + signal + ".log");
  auto r = runCli("train " + scene() + " -o " + model +
                  " --config vanilla --downscale 4 --width 16 --depth 2 --coarse 8 --fine 8 --rays 128 --steps 1000000"
                  " --save-every 0 --log-every 1 > " + log + " 2>&1 & pid=$!; " +
                  shellWaitUntil("grep -q '^step ' " + log) + "kill -" + signal + " $pid; wait $pid; s=$?; cat " + log + "; exit $s");
  EXPECT_EQ(r.code, expectedCode) << r.output;
  EXPECT_NE(r.output.find("interrupted after"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(" s compiling ("), std::string::npos) << "the summary says how long the kernels took\n" << r.output;
  auto rr = runCli("render " + model + " --orbit 1 --size 8 -o " + out);
  EXPECT_EQ(rr.code, 0) << rr.output;
  EXPECT_TRUE(std::filesystem::exists(out + "/rgb_0000.png"));
  EXPECT_TRUE(std::filesystem::exists(out + "/depth_0000.pfm"));
}

// --profile over several steps: the medians are over the last K, a kernel that only some of them
// ran (the occupancy update, every 16th step: step 16 is the 17th) says in how many.
TEST(Cli, ProfileOverTheLastStepsNamesWhatSomeStepsRan) {
  auto model = temp("profiled.vknerf");
  auto r = runCli("train " + scene() + " -o " + model + " --config fast --downscale 4 --steps 17 --profile --profile-steps 3");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("the last 3 steps, each figure its median over them"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("    rays "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("(in 1 of 3 steps)"), std::string::npos) << r.output;
  auto one = runCli("train " + scene() + " -o " + model + " --config fast --downscale 4 --steps 2 --profile");
  ASSERT_EQ(one.code, 0) << one.output;
  EXPECT_NE(one.output.find("the last step: "), std::string::npos) << one.output;
  EXPECT_EQ(one.output.find("(in "), std::string::npos) << one.output;
  EXPECT_EQ(runCli("train " + scene() + " -o " + model + " --steps 2 --profile --profile-steps 0").code, 2);
}

// render --profile prints where a view's time went, kernel by kernel (eval --profile's table), or
// says in one line that the device's queue has no timestamps; without the flag, neither.
TEST(Cli, RenderProfileSaysWhereAViewsTimeWent) {
  const vknerf::test::TempDir tmp("cli_render_profile");
  const std::string model = tmp.file("m.vknerf");
  ASSERT_EQ(runCli("train " + scene() + " -o " + model + " --downscale 4 --steps 2").code, 0);
  auto r = runCli("render " + model + " --orbit 2 --size 16 --profile -o " + tmp.file("views"));
  ASSERT_EQ(r.code, 0) << r.output;
  const bool table = r.output.find("where a view's time goes (device ms a view, the mean over 2)") != std::string::npos;
  const bool untimed = r.output.find("--profile: this device's compute queue has no timestamps") != std::string::npos;
  EXPECT_NE(table, untimed) << r.output;
  if (table) EXPECT_NE(r.output.find("  composite_forward "), std::string::npos) << r.output;
  auto plain = runCli("render " + model + " --orbit 1 --size 16 -o " + tmp.file("plain"));
  ASSERT_EQ(plain.code, 0) << plain.output;
  EXPECT_EQ(plain.output.find("where a view's time goes"), std::string::npos) << plain.output;
}

// `train` without --config trains the fast model; vanilla is asked for by name, and a resumed run
// takes the checkpoint's model whatever the default, so a vanilla checkpoint resumes as vanilla.
TEST(Cli, TrainsTheFastModelUnlessTheConfigOrTheResumedCheckpointSaysVanilla) {
  const vknerf::test::TempDir tmp("cli_default_config");
  const std::string fast = tmp.file("fast.vknerf"), vanilla = tmp.file("vanilla.vknerf"), refused = tmp.file("refused.vknerf");
  auto r = runCli("train " + scene() + " -o " + fast + " --downscale 4 --rays 128 --steps 1");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_STREQ(vknerf::modelName(vknerf::Trainer::configOf(fast).model), "fast");

  // A flag only the vanilla model reads is refused, and the message says the fast model is the default.
  r = runCli("train " + scene() + " -o " + refused + " --downscale 4 --coarse 8 --steps 1");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("--coarse applies to the vanilla model, not --config fast (the default; add --config vanilla"),
            std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(refused));

  r = runCli("train " + scene() + " -o " + vanilla +
             " --config vanilla --downscale 4 --width 16 --depth 2 --coarse 8 --fine 8 --rays 128 --steps 1");
  ASSERT_EQ(r.code, 0) << r.output;
  ASSERT_STREQ(vknerf::modelName(vknerf::Trainer::configOf(vanilla).model), "vanilla");
  r = runCli("train " + scene() + " -o " + vanilla + " --resume --downscale 4 --steps 1");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("resumed " + vanilla + " at step 1"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("done after 2 steps"), std::string::npos) << r.output;
  EXPECT_STREQ(vknerf::modelName(vknerf::Trainer::configOf(vanilla).model), "vanilla");

  // The default asked for by name is a conflicting --config, as before.
  r = runCli("train " + scene() + " -o " + vanilla + " --resume --config fast --downscale 4 --steps 1");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("--config fast conflicts with " + vanilla + "'s model vanilla"), std::string::npos) << r.output;
}

TEST(Cli, InterruptSavesALoadableCheckpoint) { interruptSavesALoadableCheckpoint("INT", 130); }
TEST(Cli, TerminateSavesALoadableCheckpoint) { interruptSavesALoadableCheckpoint("TERM", 143); }

TEST(Cli, SelfCheckPasses) {
  auto r = runCli("selfcheck --size 24 --coarse 16 --fine 16");
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("selfcheck: ok"), std::string::npos) << r.output;
}

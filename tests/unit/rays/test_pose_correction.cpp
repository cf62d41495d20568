// Camera refinement's kernels (nerf/rays/pose_correction.h: camera_correct.comp, camera_gradient.comp)
// against the CPU reference (tests/reference/rays/pose_correction.h) and, for the gradient, central
// differences of the loss it differentiates, in double.
#include <cmath>
#include <random>
#include <vector>

#include "gpu/memory/buffer.h"
#include "gpu/dispatch/recorder.h"
#include "nerf/rays/pose_correction.h"
#include "nerf/rays/rays.h"
#include "reference/rays/camera_runs.h"
#include "reference/rays/pose_correction.h"
#include "support/gpu_test.h"
#include "support/submit_once.h"

using namespace vknerf;

namespace {

class PoseCorrection : public test::GpuTest {};

// More cameras than one workgroup of the gradient's per-camera sums takes (8, gpu/per_camera_sum.glsl),
// the second workgroup partly filled.
constexpr uint32_t kCameras = 11;

std::vector<Camera> orbitCameras() {
  std::vector<Camera> cams;
  for (uint32_t i = 0; i < kCameras; ++i)
    cams.push_back(pinholeFromFocal(40, 30, 50.0f, orbitPose({0.1f, -0.2f, 0.05f}, 3.0f, 20.0f + 10.0f * i, i, kCameras)));
  return cams;
}

// Corrections of up to 0.3 rad and 0.2 units; the last camera's is zero (the series branch).
std::vector<float> randomCorrections(uint32_t seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<float> w(-0.3f, 0.3f), t(-0.2f, 0.2f);
  std::vector<float> c(kCameras * nerf::kCorrectionFloats, 0.0f);
  for (uint32_t i = 0; i + 1 < kCameras; ++i)
    for (uint32_t k = 0; k < 6; ++k) c[6 * i + k] = k < 3 ? w(gen) : t(gen);
  return c;
}

std::vector<nerf::CameraGpu> applied(Context& ctx, const std::vector<nerf::CameraGpu>& cams, const std::vector<float>& corr) {
  auto in = gpu::Buffer::of(ctx, cams), cb = gpu::Buffer::of(ctx, corr);
  gpu::Buffer out(ctx, cams.size() * sizeof(nerf::CameraGpu));
  nerf::PoseCorrection k(ctx);
  test::submitOnce(ctx, [&](gpu::Recorder& rec) { k.recordApply(rec, uint32_t(cams.size()), in, cb, out); });
  return out.download<nerf::CameraGpu>(cams.size());
}

TEST_F(PoseCorrection, ApplyMatchesReferenceAndKeepsEverythingElse) {
  const auto cams = nerf::packCameras(orbitCameras());
  const auto corr = randomCorrections(1);
  const auto got = applied(ctx(), cams, corr);
  const auto poses = orbitCameras();
  for (uint32_t i = 0; i < kCameras; ++i) {
    std::vector<double> c(corr.begin() + 6 * i, corr.begin() + 6 * i + 6);
    const auto want = ref::correctedPose<double>(poses[i].c2w, c.data());
    // Entries of a rotation times a rotation (|.| <= 1, three products and sums after sin/cos of
    // O(0.5) angles, a few ulps each) and a centre of size ~3 plus a correction: 1e-6 relative + absolute.
    for (int k = 0; k < 12; ++k) EXPECT_TRUE(test::near(got[i].c2w[k], want[k], 1e-6, 1e-6)) << "camera " << i << " entry " << k;
    for (int k = 0; k < 4; ++k) {
      EXPECT_EQ(got[i].intrinsics[k], cams[i].intrinsics[k]);
      EXPECT_EQ(got[i].size[k], cams[i].size[k]);
      EXPECT_EQ(got[i].lensK[k], cams[i].lensK[k]);
    }
  }
  // A zero correction is the identity, bit for bit: a refinement that learnt nothing changes no ray.
  const auto same = applied(ctx(), cams, std::vector<float>(kCameras * 6, 0.0f));
  for (uint32_t i = 0; i < kCameras; ++i)
    for (int k = 0; k < 12; ++k) EXPECT_EQ(same[i].c2w[k], cams[i].c2w[k]) << "camera " << i << " entry " << k;
}

TEST_F(PoseCorrection, GradientMatchesFiniteDifferences) {
  const auto poses = orbitCameras();
  const auto corr = randomCorrections(2);
  const Aabb box{{-2, -1.5f, -2}, {2, 2.5f, 1}};
  const double scale[3] = {2.0 / 4.0, 2.0 / 4.0, 2.0 / 3.0};
  const float penalty = 0.05f;
  const uint32_t R = 150, counted = 140;  // the device's ray count: the last 10 rays add nothing

  // Per ray: its camera (the batch in runs of one camera each, as training makes it), its direction in the world before correction (unit), its samples' t and
  // the dL/dp of the rows kept (the first `kept` of its marched samples).
  std::mt19937 gen(5);
  std::uniform_real_distribution<double> u(-1, 1), tDist(0.5, 4.0);
  std::uniform_int_distribution<uint32_t> marchedOf(0, 6);
  std::vector<uint32_t> camera(R), marchedOff{0}, rowOff{0};
  std::vector<std::array<double, 3>> d0(R);
  std::vector<double> t, dP;
  for (uint32_t r = 0; r < R; ++r) {
    camera[r] = ref::groupedCamera(5, r, R, kCameras);
    const double dc[3] = {0.3 * u(gen), 0.3 * u(gen), -1.0};
    const auto& m = poses[camera[r]].c2w;
    double n = 0;
    for (int k = 0; k < 3; ++k) d0[r][k] = m[4 * k] * dc[0] + m[4 * k + 1] * dc[1] + m[4 * k + 2] * dc[2], n += d0[r][k] * d0[r][k];
    for (auto& x : d0[r]) x /= std::sqrt(n);
    const uint32_t marched = marchedOf(gen), kept = marched ? std::uniform_int_distribution<uint32_t>(0, marched)(gen) : 0;
    for (uint32_t j = 0; j < marched; ++j) t.push_back(tDist(gen));
    for (uint32_t j = 0; j < kept; ++j) dP.insert(dP.end(), {u(gen), u(gen), u(gen)});
    marchedOff.push_back(marchedOff.back() + marched);
    rowOff.push_back(rowOff.back() + kept);
  }
  // The loss as a function of the corrections: each kept row's dL/dp dotted with the position it
  // maps to, x = c + tau + t exp(w) d0, plus the penalty's (penalty / 2) |correction|^2.
  auto loss = [&](const std::vector<double>& c, std::vector<double>* termSize) {
    double L = 0;
    for (double v : c) L += 0.5 * penalty * v * v;
    for (uint32_t r = 0; r < counted; ++r) {
      const double* w = &c[6 * camera[r]];
      const auto E = ref::so3Exp(w);
      const auto& m = poses[camera[r]].c2w;
      for (uint32_t j = 0; j < rowOff[r + 1] - rowOff[r]; ++j) {
        const double tj = t[marchedOff[r] + j];
        for (int k = 0; k < 3; ++k) {
          const double d = E[3 * k] * d0[r][0] + E[3 * k + 1] * d0[r][1] + E[3 * k + 2] * d0[r][2];
          const double term = dP[3 * (rowOff[r] + j) + k] * scale[k] * (m[4 * k + 3] + w[3 + k] + tj * d);
          L += term;
          if (termSize) (*termSize)[camera[r]] += std::fabs(term);
        }
      }
    }
    return L;
  };

  // The batch as the device holds it: rays from the corrected cameras, in float.
  std::vector<float> rays(size_t(R) * 8), samples(t.size() * 2 + 2, 0.0f), dPf(dP.size() / 3 * 4 + 4, 0.0f);
  std::vector<uint32_t> ids(size_t(R) * 2);
  for (uint32_t r = 0; r < R; ++r) {
    std::vector<double> c(corr.begin() + 6 * camera[r], corr.begin() + 6 * camera[r] + 6);
    const auto E = ref::so3Exp(c.data());
    const auto& m = poses[camera[r]].c2w;
    for (int k = 0; k < 3; ++k) {
      rays[8 * r + k] = float(m[4 * k + 3] + c[3 + k]);
      rays[8 * r + 4 + k] = float(E[3 * k] * d0[r][0] + E[3 * k + 1] * d0[r][1] + E[3 * k + 2] * d0[r][2]);
    }
    rays[8 * r + 3] = 0.0f, rays[8 * r + 7] = 5.0f;
    ids[2 * r] = camera[r], ids[2 * r + 1] = r;
  }
  for (size_t i = 0; i < t.size(); ++i) samples[2 * i] = float(t[i]), samples[2 * i + 1] = 0.1f;
  for (size_t i = 0; i < dP.size() / 3; ++i)
    for (int k = 0; k < 3; ++k) dPf[4 * i + k] = float(dP[3 * i + k]);

  auto rb = gpu::Buffer::of(ctx(), rays), ib = gpu::Buffer::of(ctx(), ids), mb = gpu::Buffer::of(ctx(), marchedOff),
       ob = gpu::Buffer::of(ctx(), rowOff), sb = gpu::Buffer::of(ctx(), samples), pb = gpu::Buffer::of(ctx(), dPf),
       cb = gpu::Buffer::of(ctx(), corr), nb = gpu::Buffer::of(ctx(), std::vector<uint32_t>{counted});
  auto gb = gpu::Buffer::of(ctx(), std::vector<float>(kCameras * 6, 12345.0f));
  auto penaltyBuf = gpu::Buffer::of(ctx(), std::vector<float>(kCameras, 12345.0f));
  nerf::PoseCorrection k(ctx());
  test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
    k.recordGradient(rec, {{rb, R}, ib, mb, ob, sb, pb, nb, box}, kCameras, penalty, cb, gb, gpu::BufferRange(penaltyBuf));
  });
  const auto got = gb.download<float>();
  // Each camera's penalty as the loss report reads it: (penalty / 2) |correction|^2, six float
  // squares summed (a few roundings of 2^-24 relative each: 1e-6 relative is generous).
  const auto penalties = penaltyBuf.download<float>();
  for (uint32_t cam = 0; cam < kCameras; ++cam) {
    double want = 0;
    for (int i = 0; i < 6; ++i) want += 0.5 * penalty * double(corr[6 * cam + i]) * corr[6 * cam + i];
    EXPECT_TRUE(test::near(penalties[cam], want, 1e-6, 1e-12)) << "camera " << cam << ": " << penalties[cam] << " vs " << want;
  }

  std::vector<double> c(corr.begin(), corr.end()), termSize(kCameras, 0.0);
  loss(c, &termSize);
  const double h = 1e-6;
  for (uint32_t i = 0; i < kCameras * 6; ++i) {
    const double saved = c[i];
    c[i] = saved + h;
    const double up = loss(c, nullptr);
    c[i] = saved - h;
    const double down = loss(c, nullptr);
    c[i] = saved;
    const double want = (up - down) / (2 * h);
    // The device sums a camera's terms in float (per lane, then an 8-way tree), from float rays
    // whose directions carry ~1e-7 relative error: 2^-24 times (the most terms a lane adds, under 40,
    // plus the tree's 3 levels and the rays' rounding) of the sum of the terms' sizes: 1e-5 of it.
    // The difference quotient's error, ~1e-10 absolute (rounding of L ~ 1e2 over h, and h^2
    // terms of second derivatives ~ 1e2), is far below.
    const double tol = 1e-5 * termSize[i / 6] + 1e-7;
    EXPECT_TRUE(test::near(got[i], want, 0, tol)) << "camera " << i / 6 << " parameter " << i % 6 << ": " << got[i]
                                                  << " vs " << want << " (tolerance " << tol << ")";
  }
}

}  // namespace

#pragma once
// Two loads of the same scene (a COLMAP model as text and as binary, as transforms.json, as
// poses_bounds.npy) must give the same cameras: every intrinsic, every lens coefficient, every pose
// entry and the box, compared exactly (each path parses the same numbers; nothing is recomputed
// differently).
#include <gtest/gtest.h>

#include <filesystem>

#include "vknerf/dataset.h"

namespace vknerf::test {

// The cameras and image names alone, for formats that place the scene box differently.
inline void expectSameViews(const Dataset& a, const Dataset& b) {
  ASSERT_EQ(a.cameras.size(), b.cameras.size());
  for (size_t i = 0; i < a.cameras.size(); ++i) {
    const Camera &x = a.cameras[i], &y = b.cameras[i];
    // The stem: an images_N copy of a photo may be stored in another format.
    EXPECT_EQ(std::filesystem::path(a.names[i]).stem(), std::filesystem::path(b.names[i]).stem());
    EXPECT_EQ(x.width, y.width);
    EXPECT_EQ(x.height, y.height);
    EXPECT_EQ(x.fx, y.fx);
    EXPECT_EQ(x.fy, y.fy);
    EXPECT_EQ(x.cx, y.cx);
    EXPECT_EQ(x.cy, y.cy);
    const Lens &l = x.lens, &m = y.lens;
    EXPECT_EQ(l.model, m.model);
    const float lk[] = {l.k1, l.k2, l.k3, l.k4, l.k5, l.k6, l.p1, l.p2}, mk[] = {m.k1, m.k2, m.k3, m.k4, m.k5, m.k6, m.p1, m.p2};
    for (int k = 0; k < 8; ++k) EXPECT_EQ(lk[k], mk[k]) << "camera " << i << " coefficient " << k;
    for (int k = 0; k < 16; ++k) EXPECT_EQ(x.c2w[k], y.c2w[k]) << "camera " << i << " entry " << k;
  }
}

inline void expectSameBox(const Dataset& a, const Dataset& b) {
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(a.bounds.min[k], b.bounds.min[k]);
    EXPECT_EQ(a.bounds.max[k], b.bounds.max[k]);
  }
}

inline void expectSameCameras(const Dataset& a, const Dataset& b) {
  expectSameBox(a, b);
  expectSameViews(a, b);
}

}  // namespace vknerf::test

// The easy testbed scenes' objects located twice, with and without a step, pairwise: what a
// correction changed, object by object (limb_shading_test, box_face_shading_test).
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "common/sim/testbed.h"
#include "common/sim/vision/evaluation.h"

namespace igms::object {

struct EvaluatedTwice {
  std::string name;  // scene and object
  ObjectEvaluation before, after;
};

// Every object of RandomTestbedScene(first) .. (end - 1), evaluated with `before`, then with
// `after`.
inline std::vector<EvaluatedTwice> EvaluateTestbedTwice(uint64_t first, uint64_t end,
                                                        const LocateOptions& before,
                                                        const LocateOptions& after) {
  std::vector<EvaluatedTwice> out;
  for (uint64_t seed = first; seed < end; ++seed) {
    const site::Scene scene = site::RandomTestbedScene(seed);
    const std::string name = "scene_" + std::to_string(seed);
    const auto a = EvaluateScene(scene, name, seed, before);
    const auto b = EvaluateScene(scene, name, seed, after);
    EXPECT_EQ(a.size(), b.size()) << name;
    for (size_t i = 0; i < a.size() && i < b.size(); ++i)
      out.push_back({name + " " + b[i].object_name, a[i], b[i]});
  }
  return out;
}

}  // namespace igms::object

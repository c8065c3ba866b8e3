#pragma once
#include <memory>

#include "accel.hpp"
#include "scene_data.hpp"
#include "skin/render/scene.hpp"

namespace skin::render {

struct Scene::Impl {
  SceneData data;
  std::unique_ptr<Accel> accel;
  explicit Impl(SceneData d) : data(std::move(d)), accel(std::make_unique<Accel>(data)) {}
};

// Wraps finished scene data (builds the acceleration structure).
Scene make_scene(SceneData data);

}  // namespace skin::render

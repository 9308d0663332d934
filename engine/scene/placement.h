// Standing equipment on the ground: the footprint of a placed model and the ground under it. The
// scene loader places every instance without a z with it (scene_loader.h), and build-scene checks
// each feature of a user's layers with the same computation before it writes the scene.
// Thread safety: pure functions; the heightfield is only read.
#pragma once

#include "nestwalk/geometry/volumes.h"
#include "nestwalk/terrain/footprint_ground.h"
#include "nestwalk/terrain/heightfield.h"

#include <Eigen/Core>

#include <vector>

namespace nestwalk {

/// The x-y outline (convex hull, map coordinates) of a model's hull points placed by `toLocal`
/// (local frame = map - origin); its z translation does not matter. A model with no extent gives
/// its position alone.
std::vector<Eigen::Vector2d> footprintOutline(const Eigen::Vector3d& origin, const Similarity<double>& toLocal,
                                              const std::vector<Vec3<double>>& hull);

/// The ground under that outline (terrain/footprint_ground.h: the exact lowest and highest).
terrain::GroundSpan groundUnderFootprint(const terrain::Heightfield& hf, const Eigen::Vector3d& origin,
                                         const Similarity<double>& toLocal, const std::vector<Vec3<double>>& hull);

}  // namespace nestwalk

// Builds the procedural equipment models: triangles with flat (per-face) normals, gathered into one
// osg::Geometry under an osg::Geode coloured by one osg::Material.
// Frame: whatever the caller's numbers are in; the models use metres, z up, +y forward, +x right.
// Every face is written counter-clockwise seen from outside, so its normal points outwards.
#pragma once

#include <osg/Geode>
#include <osg/Vec4>
#include <osg/ref_ptr>

#include <Eigen/Core>
#include <Eigen/Geometry>  // cross products

#include <string>
#include <vector>

namespace nestwalk::assets {

class MeshBuilder {
 public:
  /// A triangle a, b, c (counter-clockwise seen from outside); the normal is computed from it.
  void addTriangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c);
  /// A planar convex polygon (counter-clockwise seen from outside), as a fan of triangles.
  void addConvexPolygon(const std::vector<Eigen::Vector3d>& corners);
  /// A box: the points centre + rotation * x with |x_k| <= half_k (12 triangles).
  void addBox(const Eigen::Vector3d& centre, const Eigen::Vector3d& half,
              const Eigen::Matrix3d& rotation = Eigen::Matrix3d::Identity());
  /// An axis-aligned box given by its two opposite corners.
  void addBoxMinMax(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi);
  /// A right prism standing for a cylinder: `sides` vertices on each end circle of radius `radius`
  /// (circumscribed: the vertices lie on the circle), from `base` to base + length * axis (axis a
  /// unit vector). For axis z the vertices sit at angles 2 pi i / sides from +x, so with sides a
  /// multiple of 4 the prism's x and y extents are exactly 2 * radius. 4 * sides - 4 triangles.
  void addPrism(const Eigen::Vector3d& base, const Eigen::Vector3d& axis, double radius, double length, int sides);
  /// A convex profile in the model's x-z plane (counter-clockwise with x right and z up, i.e. as
  /// seen from -y) extruded along y from y0 to y1 (y1 > y0).
  void addExtrusionY(const std::vector<Eigen::Vector2d>& profileXZ, double y0, double y1);

  std::size_t triangleCount() const { return vertices_.size() / 3; }
  /// The geode: one Geometry (GL_TRIANGLES, per-vertex normals equal to the face normals) and one
  /// Material of `colour` (ambient and diffuse) on its StateSet.
  osg::ref_ptr<osg::Geode> build(const std::string& name, const osg::Vec4& colour) const;

 private:
  std::vector<Eigen::Vector3d> vertices_;  // three per triangle
  std::vector<Eigen::Vector3d> normals_;   // one per triangle
};

}  // namespace nestwalk::assets

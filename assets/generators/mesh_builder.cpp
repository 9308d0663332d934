#include "assets/generators/mesh_builder.h"

#include <osg/Geometry>
#include <osg/Material>
#include <osg/PrimitiveSet>

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace nestwalk::assets {
namespace {


/// Two unit vectors completing `axis` to a right-handed orthonormal basis (e1, e2, axis); for the
/// z axis exactly (x, y), so that prisms along z start at +x.
void basisAround(const Eigen::Vector3d& axis, Eigen::Vector3d& e1, Eigen::Vector3d& e2) {
  if (axis.x() == 0 && axis.y() == 0) {
    e1 = Eigen::Vector3d::UnitX();
    e2 = axis.z() > 0 ? Eigen::Vector3d::UnitY() : Eigen::Vector3d(0, -1, 0);
    return;
  }
  const Eigen::Vector3d helper = std::abs(axis.z()) < 0.9 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitX();
  e1 = helper.cross(axis).normalized();
  e2 = axis.cross(e1);
}

}  // namespace

void MeshBuilder::addTriangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d n = (b - a).cross(c - a);
  const double len = n.norm();
  if (!(len > 0)) throw std::logic_error("MeshBuilder: degenerate triangle");
  vertices_.push_back(a);
  vertices_.push_back(b);
  vertices_.push_back(c);
  normals_.push_back(n / len);
}

void MeshBuilder::addConvexPolygon(const std::vector<Eigen::Vector3d>& corners) {
  for (std::size_t i = 1; i + 1 < corners.size(); ++i) addTriangle(corners[0], corners[i], corners[i + 1]);
}

void MeshBuilder::addBox(const Eigen::Vector3d& centre, const Eigen::Vector3d& half, const Eigen::Matrix3d& rotation) {
  auto corner = [&](int sx, int sy, int sz) {
    return Eigen::Vector3d(centre + rotation * Eigen::Vector3d(sx * half.x(), sy * half.y(), sz * half.z()));
  };
  // Each face counter-clockwise seen from outside.
  addConvexPolygon({corner(-1, -1, -1), corner(-1, 1, -1), corner(1, 1, -1), corner(1, -1, -1)});  // bottom
  addConvexPolygon({corner(-1, -1, 1), corner(1, -1, 1), corner(1, 1, 1), corner(-1, 1, 1)});      // top
  addConvexPolygon({corner(-1, -1, -1), corner(1, -1, -1), corner(1, -1, 1), corner(-1, -1, 1)});  // -y
  addConvexPolygon({corner(-1, 1, -1), corner(-1, 1, 1), corner(1, 1, 1), corner(1, 1, -1)});      // +y
  addConvexPolygon({corner(-1, -1, -1), corner(-1, -1, 1), corner(-1, 1, 1), corner(-1, 1, -1)});  // -x
  addConvexPolygon({corner(1, -1, -1), corner(1, 1, -1), corner(1, 1, 1), corner(1, -1, 1)});      // +x
}

void MeshBuilder::addBoxMinMax(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  addBox(0.5 * (lo + hi), 0.5 * (hi - lo));
}

void MeshBuilder::addPrism(const Eigen::Vector3d& base, const Eigen::Vector3d& axis, double radius, double length,
                           int sides) {
  Eigen::Vector3d e1, e2;
  basisAround(axis, e1, e2);
  std::vector<Eigen::Vector3d> bottom, top;
  for (int i = 0; i < sides; ++i) {
    const double a = 2.0 * std::numbers::pi * i / sides;
    // Exact zeros and ones at the quarter turns keep the extents exactly 2 * radius.
    double c = std::cos(a), s = std::sin(a);
    if (4 * i % sides == 0) {
      const int q = 4 * i / sides;
      c = q == 0 ? 1 : q == 2 ? -1 : 0;
      s = q == 1 ? 1 : q == 3 ? -1 : 0;
    }
    const Eigen::Vector3d p = base + radius * (c * e1 + s * e2);
    bottom.push_back(p);
    top.push_back(p + length * axis);
  }
  for (int i = 0; i < sides; ++i) {
    const int j = (i + 1) % sides;
    addConvexPolygon({bottom[std::size_t(i)], bottom[std::size_t(j)], top[std::size_t(j)], top[std::size_t(i)]});
  }
  addConvexPolygon(top);
  std::vector<Eigen::Vector3d> reversed(bottom.rbegin(), bottom.rend());
  addConvexPolygon(reversed);
}

void MeshBuilder::addExtrusionY(const std::vector<Eigen::Vector2d>& profile, double y0, double y1) {
  // The profile is counter-clockwise seen from -y: the -y cap keeps its order, the +y cap reverses it.
  std::vector<Eigen::Vector3d> front, back;
  for (const auto& p : profile) {
    back.emplace_back(p.x(), y0, p.y());
    front.emplace_back(p.x(), y1, p.y());
  }
  const std::size_t n = profile.size();
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t j = (i + 1) % n;
    addConvexPolygon({back[i], front[i], front[j], back[j]});
  }
  std::vector<Eigen::Vector3d> frontCap(front.rbegin(), front.rend());
  addConvexPolygon(frontCap);
  addConvexPolygon(back);
}

osg::ref_ptr<osg::Geode> MeshBuilder::build(const std::string& name, const osg::Vec4& colour) const {
  osg::ref_ptr<osg::Vec3Array> v = new osg::Vec3Array;
  osg::ref_ptr<osg::Vec3Array> n = new osg::Vec3Array;
  for (std::size_t i = 0; i < vertices_.size(); ++i) {
    const Eigen::Vector3d& p = vertices_[i];
    const Eigen::Vector3d& q = normals_[i / 3];
    v->push_back(osg::Vec3(float(p.x()), float(p.y()), float(p.z())));
    n->push_back(osg::Vec3(float(q.x()), float(q.y()), float(q.z())));
  }
  osg::ref_ptr<osg::Geometry> g = new osg::Geometry;
  g->setName(name);
  g->setVertexArray(v.get());
  g->setNormalArray(n.get(), osg::Array::BIND_PER_VERTEX);
  g->addPrimitiveSet(new osg::DrawArrays(GL_TRIANGLES, 0, GLsizei(v->size())));
  osg::ref_ptr<osg::Material> m = new osg::Material;
  m->setAmbient(osg::Material::FRONT_AND_BACK, colour);
  m->setDiffuse(osg::Material::FRONT_AND_BACK, colour);
  osg::ref_ptr<osg::Geode> geode = new osg::Geode;
  geode->setName(name);
  geode->addDrawable(g.get());
  geode->getOrCreateStateSet()->setAttributeAndModes(m.get(), osg::StateAttribute::ON);
  return geode;
}

}  // namespace nestwalk::assets

// FCL's continuous collision as a peer of the contact benchmark (contact_peers.h). Conversion: the
// mesh's triangles into one fcl::BVHModel<OBBRSS> (double, exact); the box as an fcl::Box of its
// full extents placed by its axes and centre, moved by d.
// Solver: CCDC_NAIVE, the discrete test at num_max_iterations + 1 evenly spaced times, the first
// colliding one returned. It is the one FCL 0.7 (Debian 12) answers this query with: conservative
// advancement reports no contact even for a 0.5 m box moving 2 m at a single triangle 1 m away
// (for the box first it crashes in RSS::distance), and ray shooting and the polynomial solver
// refuse a box ("Invalid continuous collision setting"); FCL's issue #120 says the same. Its
// samples are placed kSampleSpacing apart along the step, so that its time of contact is within
// the benchmark's 0.1 mm agreement of the exact one: what a user of FCL would have to ask for.
#include "tools/bench/peers/contact_peers.h"

#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/narrowphase/continuous_collision.h>

#include <cmath>
#include <limits>

namespace nestwalk::bench {
namespace {

/// Metres between FCL's samples along the step: half the benchmark's 0.1 mm agreement.
constexpr double kSampleSpacing = 5e-5;
/// The request's time-of-contact tolerance, which the naive solver does not use as such; 0 makes
/// it report no contact at all (checked on the single-triangle case above), FCL's default works.
constexpr double kUnusedTolerance = 1e-4;

class FclContact : public ContactPeer {
 public:
  explicit FclContact(const TriangleMesh& mesh) {
    model_.beginModel();
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
      const Triangle t = mesh.triangle(i);
      model_.addTriangle(t[0], t[1], t[2]);
    }
    model_.endModel();
  }
  double timeOfContact(const Obb<double>& box, const Vec3<double>& d) const override {
    const fcl::Boxd shape(2 * box.halfExtents);
    fcl::Transform3d begin = fcl::Transform3d::Identity();
    begin.linear() = box.axes;
    begin.translation() = box.center;
    fcl::Transform3d end = begin;
    end.translation() += d;
    const auto samples = std::size_t(std::ceil(d.norm() / kSampleSpacing)) + 1;
    fcl::ContinuousCollisionRequestd request(samples, kUnusedTolerance, fcl::CCDM_TRANS, fcl::GST_LIBCCD, fcl::CCDC_NAIVE);
    fcl::ContinuousCollisionResultd result;
    const fcl::Transform3d still = fcl::Transform3d::Identity();
    fcl::continuousCollide(&model_, still, still, &shape, begin, end, request, result);
    return result.is_collide ? result.time_of_contact : std::numeric_limits<double>::infinity();
  }

 private:
  fcl::BVHModel<fcl::OBBRSSd> model_;
};

}  // namespace

std::unique_ptr<ContactPeer> fclContactPeer(const TriangleMesh& mesh) { return std::make_unique<FclContact>(mesh); }

}  // namespace nestwalk::bench

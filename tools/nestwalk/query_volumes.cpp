// nestwalk query volumes MODEL [--fitter NAME]: the nested volumes of a model file, as JSON.
#include "nestwalk/core/input_error.h"
#include "nestwalk/geometry/obb_fit.h"
#include "nestwalk/scene/model_geometry.h"
#include "tools/nestwalk/commands.h"

#include <nlohmann/json.hpp>

#include <cstdio>
#include <memory>

namespace nestwalk::tools {
namespace {

nlohmann::json toJson(const Vec3<double>& v) { return nlohmann::json::array({v.x(), v.y(), v.z()}); }

struct QueryVolumesOptions {
  std::string model;
  std::string fitter = "hull-search";
};

void runQueryVolumes(const QueryVolumesOptions& opts) {
  const std::optional<ObbFitter> fitter = parseFitter(opts.fitter);
  if (!fitter) throw InputError("--fitter: unknown fitter '" + opts.fitter + "' (covariance or hull-search)");
  const TriangleMesh model = loadModelGeometry(opts.model);

  Aabb<double> aabb;
  for (const auto& v : model.vertices) aabb.extend(v);
  const Obb<double> obb = fitObb(model.vertices, *fitter);

  nlohmann::json out;
  out["model"] = opts.model;
  out["triangles"] = model.triangles.size();
  out["vertices"] = model.vertices.size();
  out["aabb"] = {{"min", toJson(aabb.min)}, {"max", toJson(aabb.max)}};
  out["obb"] = {{"center", toJson(obb.center)},
                {"axes", {toJson(obb.axes.col(0)), toJson(obb.axes.col(1)), toJson(obb.axes.col(2))}},
                {"half_extents", toJson(obb.halfExtents)}};
  out["fitter"] = fitterName(*fitter);
  out["volume"] = {{"aabb", aabb.volume()}, {"obb", obb.volume()}};
  std::printf("%s\n", out.dump(2).c_str());
}

}  // namespace

void registerQueryVolumes(CLI::App& query) {
  auto opts = std::make_shared<QueryVolumesOptions>();
  CLI::App* cmd = query.add_subcommand(
      "volumes",
      "Print a model's outer AABB and fitted inner OBB as JSON (model units, under the file's transforms; "
      "obb.axes lists the unit axes u, v, w)");
  cmd->add_option("MODEL", opts->model, "Model file (any format OpenSceneGraph reads)")->required();
  cmd->add_option("--fitter", opts->fitter, "OBB fitter: covariance (Gottschalk 1996) or hull-search (tighter)")
      ->capture_default_str();
  cmd->callback([opts] { runQueryVolumes(*opts); });
}

}  // namespace nestwalk::tools

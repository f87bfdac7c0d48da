// baseline: rank the models of a modelbase by PCL descriptors on a candidate's points (issue
// 17): a global (VFH, nearest view) and a local (FPFH + RANSAC + ICP) recogniser beside canopy.
#include <algorithm>
#include <cstdio>
#include <string>

#include "baseline/baseline.h"
#include "baseline/model_cache.h"
#include "canopy/common/atomic_file.h"
#include "canopy/common/cli.h"
#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "canopy/formats/pcd.h"

namespace cm = canopy::common;
namespace bl = canopy::baseline;

int main(int argc, char** argv) {
  cm::Tool tool("baseline",
                "PCL-descriptor recogniser beside canopy: VFH nearest view and FPFH + RANSAC + "
                "ICP fitness. Writes a canopy.baseline JSON ranking every model per method.");
  bl::Params p;
  std::string in = "-", out = "-", modelbase, methods = "both", verdict, cache, hypotheses;
  int seed = 1;
  bool prepare = false;
  tool.add_input(&in, "candidate points PCD with normals (e.g. fitvox's samples)");
  tool.add_output(&out, "baseline result JSON (with --verdict: the method's verdict JSON)");
  tool.add("--modelbase", &modelbase, "directory of <model>.pcd surfaces")->required();
  tool.add("--methods", &methods, "vfh, fpfh or both")->check(CLI::IsMember({"vfh", "fpfh", "both"}));
  tool.add_length("--min-height", &p.min_height, "candidate points below this z are ground");
  tool.add_length("--voxel", &p.voxel, "voxel-grid leaf before the local descriptors");
  tool.add_length("--normal-radius", &p.normal_radius, "normal estimation radius (downsampled)");
  tool.add_length("--feature-radius", &p.feature_radius, "FPFH radius");
  tool.add_length("--inlier", &p.inlier, "RANSAC inlier and fitness distance");
  tool.add("--ransac-iterations", &p.ransac_iterations, "RANSAC iterations per model, at most 100000");
  tool.add("--icp-iterations", &p.icp_iterations, "ICP iterations per model (0 = none), at most 500");
  tool.add("--views", &p.views, "VFH model views on the sensor ring (plus the whole surface), at most 64");
  tool.add_angle("--view-elevation", &p.view_elevation, "elevation of the VFH view ring");
  tool.add("--seed", &seed, "RANSAC seed");
  tool.add("--verdict", &verdict,
           "instead of the ranking: run this one method and write its answer as a canopy.verdict "
           "(the best model, or none below --accept-<method>), for collect and score")
      ->check(CLI::IsMember({"vfh", "fpfh"}));
  tool.add("--hypotheses", &hypotheses,
           "with --verdict fpfh: also write the FPFH ranking of every model, each with its RANSAC(+ICP) "
           "pose (model -> candidate) when RANSAC converged, to this file as a canopy.match_result, "
           "for verify to check (issue 29: FPFH poses scored by verify)");
  tool.add("--accept-vfh", &p.accept_vfh,
           "--verdict vfh: smallest VFH score (1 - L1 distance / 2) of an answer");
  tool.add("--accept-fpfh", &p.accept_fpfh, "--verdict fpfh: smallest FPFH fitness of an answer");
  tool.add_flag("--prepare", &prepare,
                "instead of a ranking: compute the models' side of both methods (view VFHs; "
                "downsampled surfaces, normals, FPFH) once and write it to -o as a "
                "canopy.baseline-models file for --model-cache (-i is not read)");
  tool.add("--model-cache", &cache,
           "the models' side from this --prepare file instead of computing it (same results); "
           "refused when made from another modelbase or with other parameters");
  tool.without_threads();

  return tool.run(argc, argv, [&] {
    p.seed = static_cast<unsigned>(seed);
    bl::validate(p);
    if (!hypotheses.empty() && verdict != "fpfh") {
      throw cm::UsageError("--hypotheses needs --verdict fpfh (the poses are the FPFH method's)");
    }
    if (prepare) {
      if (!cache.empty() || !verdict.empty())
        throw cm::UsageError("--prepare with --model-cache or --verdict");
      cm::log::Phase phase("prepare");
      std::size_t n = 0;
      cm::write_file_atomic(out, bl::prepare_file(modelbase, p, &n));
      phase.done(std::to_string(n) + " models");
      return;
    }
    // With --hypotheses: the verdict and the hypotheses are written together at the end, or
    // neither (both checked now, before the work; one file named twice is a usage error).
    cm::OutputSet outputs;
    if (!hypotheses.empty()) {
      outputs.add(out, "-o");
      outputs.add(hypotheses, "--hypotheses");
    }
    cm::log::Phase read("read");
    const bl::Cloud candidate =
        bl::candidate_from_cloud(canopy::formats::read_pcd(in), cm::display_name(in), p.min_height);
    std::vector<bl::Model> models;
    bl::PreparedModels prepared;
    if (cache.empty()) {
      models = bl::read_modelbase(modelbase);
    } else {
      prepared = bl::load_prepared(cache, modelbase, p);
    }
    const std::size_t n_models = cache.empty() ? models.size() : prepared.models.size();
    read.done(std::to_string(candidate.points.size()) + " candidate points, " + std::to_string(n_models) +
              " models" + (cache.empty() ? "" : " (prepared)"));
    // The cache changes how, not what: it stays out of the outputs' parameter record.
    auto parameters = tool.parameters();
    parameters.erase(std::remove_if(parameters.begin(), parameters.end(),
                                    [](const auto& kv) {
                                      // --hypotheses is a further output: the verdict's record stays as before.
                                      return kv.first == "model-cache" || kv.first == "prepare" ||
                                             kv.first == "hypotheses";
                                    }),
                     parameters.end());

    if (!verdict.empty() && methods != "both" && methods != verdict) {
      throw cm::UsageError("--verdict " + verdict + " with --methods " + methods +
                           ": the verdict's method is run");
    }
    p.methods = verdict.empty() ? methods : verdict;
    const bl::Result r = bl::run(p, {&candidate, &models, cache.empty() ? nullptr : &prepared});
    if (verdict.empty()) {
      cm::write_file_atomic(out, bl::serialize(r, in, parameters, {in, modelbase}));
    } else {
      const double accept = verdict == "vfh" ? p.accept_vfh : p.accept_fpfh;
      const canopy::formats::Provenance prov{"baseline", CANOPY_VERSION, parameters, {in, modelbase}};
      std::string answer =
          canopy::documents::serialize_verdict(bl::to_verdict(r.methods.front(), accept, in, prov));
      if (hypotheses.empty()) {
        cm::write_file_atomic(out, std::move(answer));
      } else {
        outputs.set(out, std::move(answer));
        outputs.set(hypotheses, canopy::documents::serialize_match_result(
                                    bl::to_match_result(r.methods.front(), in, prov)));
        outputs.commit();
      }
    }
    for (const auto& m : r.methods) {
      char line[256];
      std::snprintf(line, sizeof line, "%s: best %s: score %.3f (%.3f s, %zu models)", m.method.c_str(),
                    m.models.front().model.c_str(), m.models.front().score, m.seconds, m.models.size());
      cm::log::info(line);
    }
  });
}

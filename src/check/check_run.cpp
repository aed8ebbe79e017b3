#include "check/check_run.h"

#include <cmath>
#include <iomanip>
#include <map>
#include <memory>
#include <sstream>

#include "check/foreign_gbuffer.h"
#include "check/fp32_bound.h"
#include "check/hard_cases.h"
#include "cl/cl_context.h"
#include "reference/reference.h"
#include "render/frame_setup.h"
#include "techniques/technique.h"
#include "util/error.h"
#include "util/short_text.h"

namespace ts {
namespace {

std::vector<const HardCase*> selectCases(const std::vector<std::string>& names) {
  std::vector<const HardCase*> out;
  for (const auto& c : hardCases())
    if (names.empty() || std::find(names.begin(), names.end(), c.name) != names.end())
      out.push_back(&c);
  for (const auto& n : names) {
    bool known = false;
    for (const auto& c : hardCases()) known = known || c.name == n;
    if (!known)
      throw Error("unknown hard case '" + shortText(n) + "' (see `tileshade check --list`)");
  }
  return out;
}

// Techniques are built once per configuration for the whole run: kernel builds are its slow part.
class TechniqueCache {
 public:
  explicit TechniqueCache(ClContext& cl) : cl_(cl) {}
  Technique& get(const std::string& name, const TechniqueConfig& c) {
    auto& t = cache_[name + '|' + c.key()];
    if (!t) t = createTechnique(name, cl_, c);
    return *t;
  }

 private:
  ClContext& cl_;
  std::map<std::string, std::unique_ptr<Technique>> cache_;
};

void printHeader(std::ostream& out) {
  out << std::left << std::setw(30) << "case" << std::setw(18) << "technique" << std::setw(8)
      << "layout" << std::right << std::setw(6) << "lanes" << std::setw(14) << "max err/peak"
      << std::setw(11) << "err/bound" << std::setw(9) << "NaN/inf" << std::setw(8) << "missed"
      << "  result\n";
}

void printRow(std::ostream& out, const CheckRow& r) {
  std::ostringstream err, ratio;
  err << std::scientific << std::setprecision(2) << r.maxRelPeak;
  ratio << std::scientific << std::setprecision(2) << r.worstOfBound;
  out << std::left << std::setw(30) << r.caseName << std::setw(18) << r.technique << std::setw(8)
      << toString(r.format) << std::right << std::setw(6) << r.lanes << std::setw(14) << err.str()
      << std::setw(11) << ratio.str() << std::setw(9) << r.nonFinite << std::setw(8) << r.missed
      << "  " << (r.pass() ? "pass" : "FAIL") << "\n";
  out.flush();
}

// Compares the image with the reference and the pixels' bounds.
void measure(const std::vector<glm::vec4>& image, const ReferenceImage& ref,
             const std::vector<double>& bound, CheckRow& row) {
  double worst = 0.0;
  for (size_t i = 0; i < image.size(); ++i) {
    glm::vec3 p(image[i]);
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      ++row.nonFinite;
      continue;
    }
    glm::dvec3 d = glm::abs(glm::dvec3(p) - ref.rgb[i]);
    double e = std::max({d.x, d.y, d.z});
    worst = std::max(worst, e);
    if (e > 0.0)
      row.worstOfBound = std::max(row.worstOfBound, bound[i] > 0.0 ? e / bound[i] : HUGE_VAL);
  }
  row.maxRelPeak = ref.peak > 0.0 ? worst / ref.peak : worst;
}

}  // namespace

std::vector<CheckRow> runHardCases(const CheckOptions& o, std::ostream& out) {
  std::vector<const HardCase*> cases = selectCases(o.cases);
  std::vector<std::string> techniques =
      o.techniques.empty() ? gbufferTechniqueNames() : o.techniques;
  for (const auto& t : techniques) findTechnique(t);
  ClContext cl(o.device);
  TechniqueCache cache(cl);
  out << "tileshade check: " << cases.size() << " hard cases on " << cl.deviceName() << "\n";
  printHeader(out);
  std::vector<CheckRow> rows;
  for (const HardCase* hc : cases) {
    HardCaseFrame hf = hc->build();
    // The case's own features (its shading model, material terms, light types).
    const SceneFeatures features = analyzeScene(hf.scene, nativeShadingModel(hf.scene));
    for (GBufferFormat format : o.formats) {
      PreparedFrame frame = prepareFrame(hf.scene, 0, hf.width, hf.height, format, features);
      if (hf.throughImport) frame = throughForeignGBufferFiles(frame, format);
      PreparedFrame referenceFrame =
          hf.referenceScene
              ? prepareFrame(*hf.referenceScene, 0, hf.width, hf.height, format, features)
              : PreparedFrame();
      const PreparedFrame& r = hf.referenceScene ? referenceFrame : frame;
      ReferenceImage ref = shadeReference(r.encoded, r.intrinsics, r.lights, r.ambient, 0);
      std::vector<double> bound = fp32ErrorBound(r.encoded, r.intrinsics, r.lights, r.ambient, 0);
      DeviceFrame device = frame.upload(cl);
      for (const auto& name : techniques) {
        std::vector<int> ran;
        for (int lanes : hf.lanes.empty() ? o.lanes : hf.lanes) {
          TechniqueConfig config = hf.config;
          config.format = format;
          config.features = features;
          config.lanes = lanes;
          Technique& t = cache.get(name, config);
          if (std::find(ran.begin(), ran.end(), t.lanes()) != ran.end()) continue;  // no lanes path
          ran.push_back(t.lanes());
          FrameRequest request;
          request.wantAssignment = true;
          FrameResult result = t.render(device, request);
          CheckRow row;
          row.caseName = hc->name;
          row.technique = name;
          row.format = format;
          row.lanes = t.lanes();
          measure(result.image, ref, bound, row);
          if (result.assignment)
            row.missed = countMissedContributions(*result.assignment, frame.encoded,
                                                  frame.intrinsics, frame.lights, 0);
          printRow(out, row);
          rows.push_back(row);
        }
      }
    }
  }
  return rows;
}

}  // namespace ts

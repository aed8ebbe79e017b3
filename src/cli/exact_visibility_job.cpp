#include "cli/exact_visibility_job.h"

#include "api/api_internal.h"
#include "util/error.h"

namespace ts {

ExactVisibilityResult exactVisibility(const Frame& frame) {
  Frame::Impl& f = *frame.impl();
  if (!f.scene)
    throw Error(
        "--exact-visibility needs the scene's triangles: an imported G-buffer "
        "(--gbuffer-in) has none");
  return measureAgainstExactVisibility(*f.scene, f.prepared, f.planesShadedBy(false));
}

}  // namespace ts

// libFuzzer target: the points-with-normals text format (parse_xyzn, what `restitch describe` reads),
// and SHOT and FPFH descriptors of a small point set it accepts: a Status or descriptors, never a
// crash (NaN and infinite values are accepted by the format and must be survived). scripts/fuzz.sh.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "restitch/descriptor/fpfh.hpp"
#include "restitch/descriptor/shot.hpp"
#include "restitch/descriptor/xyzn.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  restitch::Result<restitch::PointSet> points = restitch::parse_xyzn(text, "fuzz.xyzn");
  if (!points.ok() || points->size() > 256) return 0;
  restitch::DescriptorMatrix out;
  restitch::ShotDescriptor shot;
  shot.radius = 0.5f;
  (void)shot.compute(*points, *points, out, {});
  restitch::FpfhDescriptor fpfh;
  fpfh.radius = 0.5f;
  (void)fpfh.compute(*points, *points, out, {});
  return 0;
}

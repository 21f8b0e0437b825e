// pcl_descriptor_oracle - computes SHOT or FPFH with PCL, as the reference
// that tests/descriptor_test.cpp compares restitch's descriptors with.
//
//   pcl_descriptor_oracle shot|fpfh RADIUS SUPPORT.xyzn OUT.csv [QUERIES.xyzn]
//
// SUPPORT.xyzn holds `x y z nx ny nz` lines ('#' comments and blank lines
// skipped). Without QUERIES the descriptors are computed at every support
// point; with it, at the query points, with the support as PCL's search
// surface (setSearchSurface) and the support's normals. SHOT gets identity
// reference frames, one per query (setInputReferenceFrames). RADIUS is read
// as a float and widened to double, exactly as restitch's float radius is.
// OUT.csv: one row per query, "%.9g", NaN as `nan`. Exit code 0 on success.
//
// Build against Debian's libpcl-dev (PCL 1.13):
//   g++ -std=c++17 -O2 -I/usr/include/pcl-1.13 -isystem /usr/include/eigen3 \
//     tests/tools/pcl_descriptor_oracle.cpp -o pcl_descriptor_oracle \
//     -lpcl_features -lpcl_search -lpcl_kdtree -lpcl_common
//
// This program is independent of restitch's code (its own reader and writer).
#include <pcl/console/print.h>
#include <pcl/features/fpfh.h>
#include <pcl/features/shot.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace {

bool read_xyzn(const char* path, pcl::PointCloud<pcl::PointNormal>& cloud) {
  std::FILE* f = std::fopen(path, "rb");
  if (!f) return false;
  char line[4096];
  cloud.clear();
  bool dense = true;
  while (std::fgets(line, sizeof line, f)) {
    const char* s = line;
    while (*s == ' ' || *s == '\t') ++s;
    if (*s == '#' || *s == '\n' || *s == '\r' || *s == '\0') continue;
    float v[6];
    char* end = nullptr;
    for (int k = 0; k < 6; ++k) {
      v[k] = std::strtof(s, &end);
      if (end == s) {
        std::fclose(f);
        return false;
      }
      s = end;
    }
    pcl::PointNormal p;
    p.x = v[0];
    p.y = v[1];
    p.z = v[2];
    p.normal_x = v[3];
    p.normal_y = v[4];
    p.normal_z = v[5];
    p.curvature = 0.0f;
    if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))) dense = false;
    cloud.push_back(p);
  }
  std::fclose(f);
  cloud.is_dense = dense;
  return true;
}

template <class Row>
bool write_csv(const char* path, const std::vector<Row>& rows, int dim) {
  std::FILE* f = std::fopen(path, "wb");
  if (!f) return false;
  for (const Row& r : rows) {
    for (int d = 0; d < dim; ++d) {
      if (d) std::fputc(',', f);
      if (std::isnan(r[d]))
        std::fputs("nan", f);
      else
        std::fprintf(f, "%.9g", static_cast<double>(r[d]));
    }
    std::fputc('\n', f);
  }
  return std::fclose(f) == 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 5 && argc != 6) {
    std::fprintf(stderr, "usage: %s shot|fpfh RADIUS SUPPORT.xyzn OUT.csv [QUERIES.xyzn]\n", argv[0]);
    return 2;
  }
  pcl::console::setVerbosityLevel(pcl::console::L_ERROR);
  const std::string kind = argv[1];
  const double radius = static_cast<double>(std::strtof(argv[2], nullptr));
  pcl::PointCloud<pcl::PointNormal>::Ptr support(new pcl::PointCloud<pcl::PointNormal>);
  pcl::PointCloud<pcl::PointNormal>::Ptr queries(new pcl::PointCloud<pcl::PointNormal>);
  if (!read_xyzn(argv[3], *support)) {
    std::fprintf(stderr, "cannot read %s\n", argv[3]);
    return 1;
  }
  if (argc == 6) {
    if (!read_xyzn(argv[5], *queries)) {
      std::fprintf(stderr, "cannot read %s\n", argv[5]);
      return 1;
    }
  } else {
    queries = support;
  }

  if (kind == "shot") {
    pcl::SHOTEstimation<pcl::PointNormal, pcl::PointNormal, pcl::SHOT352, pcl::ReferenceFrame> est;
    pcl::PointCloud<pcl::ReferenceFrame>::Ptr frames(new pcl::PointCloud<pcl::ReferenceFrame>);
    for (std::size_t i = 0; i < queries->size(); ++i) {
      pcl::ReferenceFrame rf;
      const float identity[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
      std::memcpy(rf.rf, identity, sizeof identity);
      frames->push_back(rf);
    }
    est.setInputCloud(queries);
    if (argc == 6) est.setSearchSurface(support);
    est.setInputNormals(support);
    est.setInputReferenceFrames(frames);
    est.setRadiusSearch(radius);
    pcl::PointCloud<pcl::SHOT352> out;
    est.compute(out);
    std::vector<const float*> rows;
    for (const auto& d : out) rows.push_back(d.descriptor);
    return write_csv(argv[4], rows, 352) ? 0 : 1;
  }
  if (kind == "fpfh") {
    pcl::FPFHEstimation<pcl::PointNormal, pcl::PointNormal, pcl::FPFHSignature33> est;
    est.setInputCloud(queries);
    if (argc == 6) est.setSearchSurface(support);
    est.setInputNormals(support);
    est.setRadiusSearch(radius);
    pcl::PointCloud<pcl::FPFHSignature33> out;
    est.compute(out);
    std::vector<const float*> rows;
    for (const auto& d : out) rows.push_back(d.histogram);
    return write_csv(argv[4], rows, 33) ? 0 : 1;
  }
  std::fprintf(stderr, "unknown descriptor '%s' (shot or fpfh)\n", kind.c_str());
  return 2;
}

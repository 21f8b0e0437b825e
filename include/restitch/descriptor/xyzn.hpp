// restitch/descriptor/xyzn.hpp - the text formats of `restitch describe`:
// points with normals in, descriptors as CSV out.
//
// read_xyzn(path) reads an .xyzn file (parse_xyzn(text, name) the same bytes held in memory): one point per line, six numbers
// `x y z nx ny nz` separated by spaces or tabs. Blank lines and lines whose
// first non-blank character is '#' are skipped; a trailing '\r' (CRLF files)
// is ignored. Numbers are parsed with strtof (C locale assumed), so `nan` and
// `inf` are accepted (a NaN normal or position is meaningful to the
// descriptors: see shot.hpp, fpfh.hpp). Any other line is a parse_error whose
// message names the file and the 1-based line number. A file with no point is
// valid and gives an empty PointSet. Normals are read as given (not
// normalised).
//
// write_descriptor_csv(path, D) writes one line per row of D, values
// separated by ',' with "%.9g" (enough digits to round-trip any float), NaN
// written as `nan` (and infinities as `inf`/`-inf`). It writes
// `path + ".tmp"` first and renames it over `path`, so `path` is never left
// half-written; on any error the temporary file is removed and an io_error
// returned. (std::rename replaces an existing file on POSIX; on Windows it
// fails if `path` exists.)
//
// Cost: linear in the file size; read_xyzn holds the numbers once in a
// std::vector before copying them into the PointSet.
#pragma once

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

#include "restitch/descriptor/descriptor.hpp"
#include "restitch/detail/file.hpp"
#include "restitch/status.hpp"

namespace restitch {

/// Parses `x y z nx ny nz` lines held in memory into a PointSet; `name` (a path, or any label) starts the
/// error messages. See the file comment.
template <class = void>
Result<PointSet> parse_xyzn(std::string_view text, const std::string& name) {
  return detail::guarded("parse_xyzn", [&]() -> Result<PointSet> {
    std::vector<float> values;
    std::string line;
    long line_number = 0;
    std::size_t pos = 0;
    while (pos < text.size()) {
      std::size_t end = text.find('\n', pos);
      if (end == std::string_view::npos) end = text.size();
      line.assign(text.data() + pos, end - pos);
      pos = end + 1;
      ++line_number;
      if (!line.empty() && line.back() == '\r') line.pop_back();
      std::size_t first = line.find_first_not_of(" \t");
      if (first == std::string::npos || line[first] == '#') continue;
      const char* s = line.c_str();
      float v[6];
      int count = 0;
      bool bad = line.find('\0') != std::string::npos;  // strtof would stop there
      while (!bad) {
        while (*s == ' ' || *s == '\t') ++s;
        if (*s == '\0') break;
        if (count == 6) {
          bad = true;
          break;
        }
        char* end_number = nullptr;
        const float x = std::strtof(s, &end_number);
        if (end_number == s || (*end_number != '\0' && *end_number != ' ' && *end_number != '\t')) {
          bad = true;
          break;
        }
        v[count++] = x;
        s = end_number;
      }
      if (bad || count != 6) {
        if (line.size() > 80) line = line.substr(0, 80) + "...";
        return error(StatusCode::parse_error, name + ":" + std::to_string(line_number) +
                                                  ": expected 6 numbers 'x y z nx ny nz', got '" + line + "'");
      }
      values.insert(values.end(), v, v + 6);
    }
    PointSet ps;
    const Eigen::Index n = static_cast<Eigen::Index>(values.size() / 6);
    ps.points.resize(n, 3);
    ps.normals.resize(n, 3);
    for (Eigen::Index i = 0; i < n; ++i) {
      for (int d = 0; d < 3; ++d) {
        ps.points(i, d) = values[static_cast<std::size_t>(6 * i + d)];
        ps.normals(i, d) = values[static_cast<std::size_t>(6 * i + 3 + d)];
      }
    }
    return ps;
  });
}

/// Reads an .xyzn file into a PointSet (parse_xyzn on its bytes); io_error when it cannot be read.
template <class = void>
Result<PointSet> read_xyzn(const std::string& path) {
  return detail::guarded("read_xyzn", [&]() -> Result<PointSet> {
    std::vector<std::uint8_t> bytes;
    RESTITCH_TRY(detail::read_file(path, bytes));
    return parse_xyzn(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), path);
  });
}

/// Writes D as CSV through a temporary file; see the file comment.
template <class = void>
Status write_descriptor_csv(const std::string& path, const DescriptorMatrix& D) {
  return detail::guarded("write_descriptor_csv", [&]() -> Status {
    const std::string tmp = path + ".tmp";
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    if (!f) return error(StatusCode::io_error, "cannot open '" + tmp + "' for writing");
    bool ok = true;
    char buf[32];
    for (Eigen::Index i = 0; i < D.rows() && ok; ++i) {
      for (Eigen::Index j = 0; j < D.cols() && ok; ++j) {
        const float x = D(i, j);
        const char* text = buf;
        if (std::isnan(x)) {
          text = "nan";
        } else {
          std::snprintf(buf, sizeof buf, "%.9g", static_cast<double>(x));
        }
        if (j > 0 && std::fputc(',', f) == EOF) ok = false;
        if (ok && std::fputs(text, f) == EOF) ok = false;
      }
      if (ok && std::fputc('\n', f) == EOF) ok = false;
    }
    if (std::fclose(f) != 0) ok = false;
    if (!ok) {
      std::remove(tmp.c_str());
      return error(StatusCode::io_error, "error while writing '" + tmp + "'");
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
      std::remove(tmp.c_str());
      return error(StatusCode::io_error, "cannot rename '" + tmp + "' to '" + path + "'");
    }
    return Status();
  });
}

}  // namespace restitch

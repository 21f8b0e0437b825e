// restitch/solver/mrf_io.hpp - a labelling problem as a plain-text file.
//
// What `restitch resize --dump-mrf FILE` writes and `restitch solve FILE`
// reads, so a solver can be studied, compared or replaced on the exact
// problem a resize produced. The format, version 1:
//
//   restitch-mrf 1
//   nodes N labels M edges E
//   N lines of M numbers          unary(i, 0) ... unary(i, M-1), node i = 0..N-1
//   then for each edge e = 0..E-1:
//     i j                         the two nodes of edge e (0-based, i != j)
//     M lines of M numbers        row a: pairwise(e, a, 0) ... pairwise(e, a, M-1)
//                                 (a = label of node i, the column that of node j)
//
// Numbers are separated by spaces or tabs; every number is finite. The
// writer prints doubles with "%.17g", so read_mrf(write_mrf(P)) gives the
// same doubles bit for bit. The reader also skips empty lines and lines whose
// first non-blank character is '#' (comments; the writer writes none), and
// accepts "\r\n" line ends. Numbers are read with strtod, i.e. in the C
// locale (the default unless the program calls setlocale). Files with more
// than read_mrf_max_values = N M + E M^2 numbers (1e8, 800 MB in memory) are
// refused with StatusCode::too_large; so are N > 1e8, M > 1e5 or E > 1e9.
//
// Cost: write and read are O(N M + E M^2) numbers (about 24 bytes each in
// the file). read_mrf holds the whole file in memory while parsing.
#pragma once

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "restitch/detail/file.hpp"
#include "restitch/solver/mrf.hpp"
#include "restitch/status.hpp"

namespace restitch {

/// Largest number count N M + E M^2 that read_mrf() accepts.
inline constexpr double read_mrf_max_values = 1e8;

namespace detail {

/// Line-by-line reader over a file held in memory; skips blank and '#' lines.
class MrfLines {
 public:
  MrfLines(std::string_view text, std::string path) : text_(text), path_(std::move(path)) {}

  /// The next line with content; false at the end of the file.
  template <class = void>
  bool next(std::string_view& line) {
    while (pos_ < text_.size()) {
      std::size_t end = text_.find('\n', pos_);
      if (end == std::string_view::npos) end = text_.size();
      std::string_view l(text_.data() + pos_, end - pos_);
      pos_ = end + 1;
      ++line_no_;
      if (!l.empty() && l.back() == '\r') l.remove_suffix(1);
      const std::size_t first = l.find_first_not_of(" \t");
      if (first == std::string_view::npos || l[first] == '#') continue;
      line = l;
      return true;
    }
    ++line_no_;
    return false;
  }

  Status fail(StatusCode code, const std::string& what) const {
    return error(code, path_ + ":" + std::to_string(line_no_) + ": " + what);
  }
  Status parse_error(const std::string& what) const { return fail(StatusCode::parse_error, what); }

 private:
  std::string_view text_;
  std::string path_;
  std::size_t pos_ = 0;
  int line_no_ = 0;
};

/// Splits a line into tokens separated by spaces or tabs.
template <class = void>
void split_tokens(std::string_view line, std::vector<std::string_view>& out) {
  out.clear();
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    const std::size_t b = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
    if (i > b) out.push_back(line.substr(b, i - b));
  }
}

/// A finite double from a token; false when it is not one.
template <class = void>
bool parse_double(std::string_view token, double& value) {
  char buf[64];
  if (token.empty() || token.size() >= sizeof buf) return false;
  token.copy(buf, token.size());
  buf[token.size()] = '\0';
  char* end = nullptr;
  value = std::strtod(buf, &end);  // ERANGE on underflow is fine: the denormal or zero is what was written
  return end == buf + token.size() && std::isfinite(value);
}

/// A non-negative decimal integer up to `max` from a token.
template <class = void>
bool parse_count(std::string_view token, long long max, long long& value) {
  if (token.empty() || token.size() > 18) return false;
  value = 0;
  for (char c : token) {
    if (c < '0' || c > '9') return false;
    value = value * 10 + (c - '0');
  }
  return value <= max;
}

template <class = void>
std::string quoted(std::string_view token) {
  std::string s(token.substr(0, 40));
  if (token.size() > 40) s += "...";
  return "'" + s + "'";
}

/// Reads one line of exactly `count` numbers into out[0..count).
template <class = void>
Status read_row(MrfLines& lines, std::vector<std::string_view>& tokens, int count, double* out,
                       const std::string& what) {
  std::string_view line;
  if (!lines.next(line))
    return lines.parse_error("the file ends early: expected " + what + " (" + std::to_string(count) + " numbers)");
  split_tokens(line, tokens);
  if (static_cast<long long>(tokens.size()) != count)
    return lines.parse_error("expected " + what + ": " + std::to_string(count) + " numbers, found " +
                             std::to_string(tokens.size()));
  for (int k = 0; k < count; ++k)
    if (!parse_double(tokens[static_cast<std::size_t>(k)], out[k]))
      return lines.parse_error("in " + what + ", value " + std::to_string(k + 1) + " " +
                               quoted(tokens[static_cast<std::size_t>(k)]) + " is not a finite number");
  return Status();
}

}  // namespace detail

/// Writes `problem` in the format above to `path`: first to path + ".tmp",
/// then renamed over `path`, so a reader never sees half a file. Returns
/// invalid_argument for a term that is not finite or an edge that is not two
/// different nodes in range (nothing is left behind), io_error when the file
/// cannot be written or renamed. Cost O(N M + E M^2).
template <class P>
Status write_mrf(const std::string& path, const P& problem) {
  return detail::guarded("write_mrf", [&]() -> Status {
    static_assert(is_labelling_problem_v<P>,
                  "restitch::write_mrf: the problem type does not satisfy the labelling problem contract "
                  "(see restitch/solver/mrf.hpp)");
    const int n = problem.node_count(), m = problem.label_count(), edges = problem.edge_count();
    if (n < 0 || m < 0 || edges < 0) return error(StatusCode::invalid_argument, "write_mrf: negative problem size");
    if (n > 0 && m < 1) return error(StatusCode::invalid_argument, "write_mrf: the problem has nodes but no labels");
    const std::string tmp = path + ".tmp";
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    if (!f) return error(StatusCode::io_error, "cannot open '" + tmp + "' for writing");
    Status bad;
    const auto put = [&](double v, const char* sep, const char* what, int index) {
      if (!bad.ok()) return;
      if (!std::isfinite(v)) {
        bad = error(StatusCode::invalid_argument,
                    std::string("write_mrf: a ") + what + " term of " + std::to_string(index) + " is not finite");
        return;
      }
      std::fprintf(f, "%.17g%s", v, sep);
    };
    std::fprintf(f, "restitch-mrf 1\nnodes %d labels %d edges %d\n", n, m, edges);
    for (int i = 0; i < n && bad.ok(); ++i)
      for (int a = 0; a < m; ++a) put(problem.unary(i, a), a + 1 < m ? " " : "\n", "unary", i);
    for (int e = 0; e < edges && bad.ok(); ++e) {
      const std::pair<int, int> ij = problem.edge(e);
      if (ij.first < 0 || ij.first >= n || ij.second < 0 || ij.second >= n || ij.first == ij.second) {
        bad = error(StatusCode::invalid_argument,
                    "write_mrf: edge " + std::to_string(e) + " does not join two different nodes in range");
        break;
      }
      std::fprintf(f, "%d %d\n", ij.first, ij.second);
      for (int a = 0; a < m; ++a)
        for (int b = 0; b < m; ++b) put(problem.pairwise(e, a, b), b + 1 < m ? " " : "\n", "pairwise", e);
    }
    const bool write_failed = std::ferror(f) != 0;
    const bool close_failed = std::fclose(f) != 0;
    if (!bad.ok() || write_failed || close_failed) {
      std::remove(tmp.c_str());
      return bad.ok() ? error(StatusCode::io_error, "writing '" + tmp + "' failed (disk full?)") : bad;
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
      std::remove(tmp.c_str());
      return error(StatusCode::io_error, "cannot rename '" + tmp + "' to '" + path + "'");
    }
    return Status();
  });
}

/// Reads a problem written by write_mrf() (or by hand, in the format above).
/// Errors: io_error (cannot open or read), parse_error with "path:line: what"
/// (wrong header, a count that is not a number, a row with the wrong number
/// of values, a value that is not a finite number, an edge out of range or
/// joining a node to itself, missing or extra lines), unsupported (a newer
/// format version), too_large (sizes past the limits above).
/// parse_mrf reads the same from bytes held in memory; `path` only names them in messages.
template <class = void>
Result<TableMrf> parse_mrf(std::string_view text, const std::string& path) {
  return detail::guarded("parse_mrf", [&]() -> Result<TableMrf> {
    detail::MrfLines lines(text, path);
    std::vector<std::string_view> tok;
    std::string_view line;

    if (!lines.next(line)) return lines.parse_error("empty file; expected the header 'restitch-mrf 1'");
    detail::split_tokens(line, tok);
    if (tok.size() != 2 || tok[0] != "restitch-mrf")
      return lines.parse_error("not a restitch MRF file: expected the header 'restitch-mrf 1'");
    long long version = 0;
    if (!detail::parse_count(tok[1], 1000000, version))
      return lines.parse_error("the format version " + detail::quoted(tok[1]) + " is not a number");
    if (version != 1)
      return lines.fail(StatusCode::unsupported,
                        "format version " + std::to_string(version) + " is not supported; this reader knows version 1");

    if (!lines.next(line)) return lines.parse_error("the file ends early: expected 'nodes N labels M edges E'");
    detail::split_tokens(line, tok);
    if (tok.size() != 6 || tok[0] != "nodes" || tok[2] != "labels" || tok[4] != "edges")
      return lines.parse_error("expected 'nodes N labels M edges E'");
    long long sizes[3];
    const long long limits[3] = {100000000LL, 100000LL, 1000000000LL};
    const char* names[3] = {"nodes", "labels", "edges"};
    for (int k = 0; k < 3; ++k) {
      const std::string_view t = tok[static_cast<std::size_t>(2 * k + 1)];
      if (!detail::parse_count(t, 999999999999999999LL, sizes[k]))
        return lines.parse_error("the number of " + std::string(names[k]) + " " + detail::quoted(t) +
                                 " is not a non-negative integer");
      if (sizes[k] > limits[k])
        return lines.fail(StatusCode::too_large, std::to_string(sizes[k]) + " " + names[k] +
                                                     " is more than read_mrf accepts (" + std::to_string(limits[k]) +
                                                     ")");
    }
    const long long n = sizes[0], m = sizes[1], edges = sizes[2];
    const double values = double(n) * double(m) + double(edges) * double(m) * double(m);
    if (values > read_mrf_max_values)
      return lines.fail(StatusCode::too_large, "the problem holds " + std::to_string(values) +
                                                   " numbers (N M + E M^2); read_mrf accepts at most 1e8");
    if (n > 0 && m == 0) return lines.parse_error("a problem with nodes needs at least one label");
    // Every value takes at least two bytes ("0 "), every edge's node pair four: a file too short for what
    // it declares is refused before the tables are allocated.
    if (values * 2 + double(edges) * 4 > double(text.size()))
      return lines.parse_error("the file ends early: it declares " + std::to_string(n) + " nodes, " +
                               std::to_string(m) + " labels and " + std::to_string(edges) +
                               " edges, more numbers than its " + std::to_string(text.size()) + " bytes can hold");

    TableMrf problem(static_cast<int>(n), static_cast<int>(m));
    // One unary row, or one pairwise table when there are edges (whose M^2 the bound above counted; without
    // edges it did not, and 1e5 labels squared would ask for 80 GB).
    std::vector<double> row(static_cast<std::size_t>(m) * static_cast<std::size_t>(edges > 0 ? m : 1));
    for (int i = 0; i < n; ++i) {
      RESTITCH_TRY(detail::read_row(lines, tok, static_cast<int>(m), row.data(),
                                    "the unary terms of node " + std::to_string(i)));
      for (int a = 0; a < m; ++a) problem.set_unary(i, a, row[static_cast<std::size_t>(a)]);
    }
    for (long long e = 0; e < edges; ++e) {
      const std::string which = "edge " + std::to_string(e);
      if (!lines.next(line)) return lines.parse_error("the file ends early: expected the nodes 'i j' of " + which);
      detail::split_tokens(line, tok);
      long long i = 0, j = 0;
      if (tok.size() != 2 || !detail::parse_count(tok[0], n - 1, i) || !detail::parse_count(tok[1], n - 1, j))
        return lines.parse_error("expected the nodes 'i j' of " + which + ": two node ids in [0, " + std::to_string(n) +
                                 ")");
      if (i == j) return lines.parse_error(which + " joins node " + std::to_string(i) + " to itself");
      for (int a = 0; a < m; ++a)
        RESTITCH_TRY(detail::read_row(lines, tok, static_cast<int>(m), row.data() + static_cast<std::size_t>(a) * m,
                                      "row " + std::to_string(a) + " of the pairwise table of " + which));
      problem.add_edge(static_cast<int>(i), static_cast<int>(j), row);
    }
    if (lines.next(line)) return lines.parse_error("unexpected data after the last edge");
    return problem;
  });
}

/// Reads a problem file (parse_mrf on its bytes); io_error when it cannot be read.
template <class = void>
Result<TableMrf> read_mrf(const std::string& path) {
  return detail::guarded("read_mrf", [&]() -> Result<TableMrf> {
    std::vector<std::uint8_t> bytes;
    RESTITCH_TRY(detail::read_file(path, bytes));
    return parse_mrf(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), path);
  });
}

}  // namespace restitch

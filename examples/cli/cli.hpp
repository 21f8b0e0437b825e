// Shared pieces of the restitch command-line tool: exit codes, the progress
// bar, JSON output and the subcommand registry.
#pragma once

#include <CLI/CLI.hpp>
#include <cctype>
#include <cmath>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "restitch/io/gltf.hpp"
#include "restitch/progress.hpp"
#include "restitch/status.hpp"

namespace restitch::cli {

/// Exit codes, documented in `restitch --help` and the README.
enum ExitCode : int {
  exit_ok = 0,
  exit_usage = 2,      ///< bad command line
  exit_input = 3,      ///< the input cannot be read (missing, not glTF, corrupt)
  exit_model = 4,      ///< the model is readable but unusable (empty, NaN, unsupported content)
  exit_request = 5,    ///< the request is refused (out of range, too many labels)
  exit_output = 6,     ///< the output cannot be written
  exit_flagged = 7,    ///< resize --strict: the result check flagged the result (the output is written)
  exit_internal = 70,  ///< a bug
};

/// Maps a library Status to an exit code (input side unless `writing`).
int exit_code_for(const Status& s, bool writing = false);

/// Prints "restitch: <message>" on stderr and returns the exit code.
int fail(const Status& s, bool writing = false);

/// A progress bar on stderr when it is a terminal, silent otherwise.
Progress terminal_progress();

/// Writes `j` to FILE, or to stdout for "-" (temporary file + rename for files).
Status write_json(const nlohmann::json& j, const std::string& where);

/// x for printing: +0 for -0 (never "-0") and for a component under 1e-4 of the vector's `length`
/// (refinement noise: an ICP-refined offset is good to about 1e-4 of its length).
inline double printable(double x, double length = 0) { return x == 0 || std::abs(x) < 1e-4 * length ? 0.0 : x; }

/// The analysis policies chosen on the command line (--descriptor, --matcher, --detector).
struct PolicyNames {
  std::string descriptor = "shot", matcher = "reduced", detector = "histogram";
  std::vector<double> offsets;  ///< --offsets: x,y,z triples (model units) made principal first
  GltfLimits limits;            ///< --max-vertices, --max-triangles
  int threads = 0;              ///< --threads: analysis workers (0: every hardware thread)
};

/// The -o of a model: a path ending in .glb or .gltf (any case); anything else is a command-line mistake
/// (exit 2), found before the input is read.
inline CLI::Validator gltf_output_path() {
  return CLI::Validator(
      [](const std::string& path) {
        std::string ext = path.size() >= 5 ? path.substr(path.size() - 5) : path;
        for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
        const bool ok = ext == ".gltf" || (ext.size() == 5 && ext.substr(1) == ".glb");
        return ok ? std::string() : "the output must end in .glb or .gltf: " + path;
      },
      "PATH.glb|PATH.gltf");
}

/// Adds --max-vertices and --max-triangles (what a loaded model may have at most; GltfLimits).
void add_limit_options(CLI::App* cmd, GltfLimits& limits);

/// Each subcommand registers itself: it adds a CLI11 subcommand and sets a
/// callback that stores its exit code in `*exit_code`.
using Registrar = std::function<void(CLI::App& app, int* exit_code)>;
void register_info(CLI::App& app, int* exit_code);
void register_sample(CLI::App& app, int* exit_code);
void register_convert(CLI::App& app, int* exit_code);
void register_analysis_commands(CLI::App& app, int* exit_code);  // analyze, describe
void register_retarget_commands(CLI::App& app, int* exit_code);  // resize, solve

}  // namespace restitch::cli

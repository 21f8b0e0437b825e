// restitch: resize man-made 3D models along their repeats.
#include <unistd.h>
#ifdef __EMSCRIPTEN__
#include <emscripten.h>
#endif
#include <cstdio>
#include <exception>
#include <iostream>
#include <new>

#include "cli.hpp"
#include "restitch/detail/file.hpp"

namespace restitch::cli {

int exit_code_for(const Status& s, bool writing) {
  if (writing && s.code() == StatusCode::io_error) return exit_output;
  switch (s.code()) {
    case StatusCode::ok:
      return exit_ok;
    case StatusCode::io_error:
    case StatusCode::parse_error:
      return exit_input;
    case StatusCode::invalid_mesh:
    case StatusCode::unsupported:
    case StatusCode::no_repetition:
      return exit_model;
    case StatusCode::invalid_argument:
    case StatusCode::too_large:
    case StatusCode::cancelled:
      return exit_request;
    case StatusCode::internal:
      return exit_internal;
  }
  return exit_internal;
}

int fail(const Status& s, bool writing) {
  std::fprintf(stderr, "restitch: %s\n", s.message().c_str());
  return exit_code_for(s, writing);
}

// Whether standard error is a terminal. Under node (the WebAssembly build, `npx restitch`) Emscripten's
// isatty answers yes for every standard stream, so node's own answer is asked.
bool stderr_is_terminal() {
#ifdef __EMSCRIPTEN__
  return EM_ASM_INT({ return typeof require === 'function' && require('tty').isatty($0) ? 1 : 0; }, STDERR_FILENO) != 0;
#else
  return isatty(STDERR_FILENO) != 0;
#endif
}

Progress terminal_progress() {
  if (!stderr_is_terminal()) return Progress();
  return Progress([last = std::string(), last_pct = -1](std::string_view stage, double f) mutable {
    const int pct = int(f * 100.0 + 0.5);
    if (stage == last && pct == last_pct) return true;
    const int width = 30, filled = int(f * width + 0.5);
    std::fprintf(stderr, "\r  %-12.*s [%.*s%*s] %3d%%", int(stage.size()), stage.data(), filled,
                 "##############################", width - filled, "", pct);
    if (f >= 1.0) std::fprintf(stderr, "\r%*s\r", 60, "");
    std::fflush(stderr);
    last = std::string(stage), last_pct = pct;
    return true;
  });
}

Status write_json(const nlohmann::json& j, const std::string& where) {
  const std::string text = j.dump(2) + "\n";
  if (where == "-") {
    std::fwrite(text.data(), 1, text.size(), stdout);
    return {};
  }
  return detail::write_file_atomic(where, text.data(), text.size());
}

}  // namespace restitch::cli

int main(int argc, char** argv) {
  using namespace restitch::cli;
  CLI::App app{
      "restitch: resize man-made 3D models (shelves, facades, fences, connectors) along their repeats.\n"
      "Exit codes: 0 ok, 2 bad command line, 3 input unreadable, 4 model unusable,\n"
      "5 request refused, 6 output not writable, 7 the result needs a look (resize --strict),\n"
      "70 internal error.",
      "restitch"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "restitch 0.1.0");
  int exit_code = exit_ok;
  register_info(app, &exit_code);
  register_sample(app, &exit_code);
  register_convert(app, &exit_code);
  register_analysis_commands(app, &exit_code);
  register_retarget_commands(app, &exit_code);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return exit_usage;
  } catch (const std::bad_alloc&) {  // the library returns a Status; this is the tool's own code (JSON, text)
    std::fputs("restitch: out of memory\n", stderr);
    return exit_request;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "restitch: internal error: %s\n", e.what());
    return exit_internal;
  }
  return exit_code;
}

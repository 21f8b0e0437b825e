// restitch sample --list | restitch sample NAME -o OUT.glb [--PARAM VALUE ...]
#include <cstdio>
#include <cstdlib>
#include <map>

#include "cli.hpp"
#include "restitch/io/gltf.hpp"
#include "restitch/families/families.hpp"

namespace restitch::cli {

void register_sample(CLI::App& app, int* exit_code) {
  struct Args {
    std::string name, output;
    bool list = false;
  };
  auto args = std::make_shared<Args>();
  std::string footer = "Samples and their parameters (--NAME VALUE):\n";
  for (const families::SampleInfo& info : families::catalog()) {
    footer += "  " + info.name + ": " + info.description + "\n   ";
    for (const families::Parameter& p : info.parameters)
      footer += " --" + p.name + " " + CLI::detail::to_string(p.value);
    footer += "\n";
  }
  CLI::App* cmd = app.add_subcommand("sample", "Generate a parametric sample model with exactly known repeats");
  cmd->add_flag("--list", args->list, "list the samples, one per line, name first");
  cmd->add_option("name", args->name, "sample name (see --list)");
  cmd->add_option("-o,--output", args->output, "output model (.glb or .gltf)")->check(gltf_output_path());
  cmd->allow_extras();
  cmd->footer(footer);
  cmd->callback([args, exit_code, cmd] {
    if (args->list) {
      for (const families::SampleInfo& info : families::catalog())
        std::printf("%s\t%s\n", info.name.c_str(), info.description.c_str());
      *exit_code = exit_ok;
      return;
    }
    if (args->name.empty() || args->output.empty()) {
      std::fprintf(stderr, "restitch sample: give a NAME and -o OUT.glb, or --list (see --help)\n");
      *exit_code = exit_usage;
      return;
    }
    // Extras are --PARAM VALUE pairs.
    std::map<std::string, double> overrides;
    const std::vector<std::string> extras = cmd->remaining();
    for (std::size_t i = 0; i < extras.size(); ++i) {
      const std::string& key = extras[i];
      if (key.rfind("--", 0) != 0 || key.size() < 3 || i + 1 >= extras.size()) {
        std::fprintf(stderr, "restitch sample: parameters are given as --NAME VALUE; cannot read '%s'\n", key.c_str());
        *exit_code = exit_usage;
        return;
      }
      const std::string& text = extras[++i];
      char* end = nullptr;
      const double v = std::strtod(text.c_str(), &end);
      if (end == text.c_str() || *end != '\0') {
        std::fprintf(stderr, "restitch sample: %s needs a number, got '%s'\n", key.c_str(), text.c_str());
        *exit_code = exit_usage;
        return;
      }
      overrides[key.substr(2)] = v;
    }
    Result<families::SampleModel> model = families::generate(args->name, overrides);
    if (!model) {
      *exit_code = fail(model.status());
      return;
    }
    if (Status s = save_gltf(model->mesh, args->output); !s) {
      *exit_code = fail(s, true);
      return;
    }
    std::printf("wrote %s: sample '%s', %zu vertices, %zu triangles\n", args->output.c_str(), args->name.c_str(),
                model->mesh.vertex_count(), model->mesh.triangle_count());
    for (std::size_t g = 0; g < model->generators.size(); ++g) {
      const auto& v = model->generators[g];
      std::printf("  repeat %zu: %d x (%g, %g, %g)  [--%s]\n", g + 1, model->counts[g], v.x(), v.y(), v.z(),
                  model->count_parameters[g].c_str());
    }
    *exit_code = exit_ok;
  });
}

}  // namespace restitch::cli

// restitch info IN [--json FILE|-]: what a glTF file holds, as restitch reads it.
#include <cstdio>

#include "cli.hpp"
#include "restitch/io/gltf.hpp"
#include "restitch/mesh_boundary.hpp"

namespace restitch::cli {

void register_info(CLI::App& app, int* exit_code) {
  struct Args {
    std::string input, json;
    GltfLimits limits;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "info",
      "Print meshes, primitives, materials, textures, vertices, triangles, boundary edges, bounding box and warnings "
      "of a glTF model");
  cmd->add_option("input", args->input, "input model (.glb or .gltf)")->required();
  cmd->add_option("--json", args->json, "also write the figures as JSON to FILE, or - for standard output");
  add_limit_options(cmd, args->limits);
  cmd->callback([args, exit_code] {
    GltfLoadReport report;
    Result<Mesh> mesh = load_gltf(args->input, &report, args->limits);
    if (!mesh) {
      *exit_code = fail(mesh.status());
      return;
    }
    const BoundingBox box = bounding_box(*mesh);
    nlohmann::json j;
    j["file"] = args->input;
    j["meshes"] = report.meshes;
    j["nodes"] = report.nodes;
    j["primitives"] = report.primitives;
    j["groups"] = mesh->groups.size();
    j["materials"] = report.materials;
    j["textures"] = report.textures;
    j["images"] = report.images;
    j["vertices"] = mesh->vertex_count();
    j["triangles"] = mesh->triangle_count();
    const std::size_t open_edges = boundary_edge_count(*mesh);
    j["boundary_edges"] = open_edges;
    j["bbox_min"] = {box.min.x(), box.min.y(), box.min.z()};
    j["bbox_max"] = {box.max.x(), box.max.y(), box.max.z()};
    j["bbox_size"] = {box.size().x(), box.size().y(), box.size().z()};
    j["warnings"] = report.warnings;
    if (args->json != "-") {
      std::printf("%s\n", args->input.c_str());
      std::printf("  meshes %zu, nodes %zu, triangle primitives %zu (in %zu groups)\n", report.meshes, report.nodes,
                  report.primitives, mesh->groups.size());
      std::printf("  materials %zu, textures %zu, images %zu\n", report.materials, report.textures, report.images);
      std::printf("  vertices %zu, triangles %zu\n", mesh->vertex_count(), mesh->triangle_count());
      std::printf("  boundary edges (positions welded) %zu\n", open_edges);
      std::printf("  bounding box min (%g, %g, %g) max (%g, %g, %g) size %g x %g x %g\n", box.min.x(), box.min.y(),
                  box.min.z(), box.max.x(), box.max.y(), box.max.z(), box.size().x(), box.size().y(), box.size().z());
      std::printf("  warnings: %s\n", report.warnings.empty() ? "none" : "");
      for (const std::string& w : report.warnings) std::printf("    - %s\n", w.c_str());
    }
    if (!args->json.empty())
      if (Status s = write_json(j, args->json); !s) {
        *exit_code = fail(s, true);
        return;
      }
    *exit_code = exit_ok;
  });
}

}  // namespace restitch::cli

namespace restitch::cli {

void register_convert(CLI::App& app, int* exit_code) {
  struct Args {
    std::string input, output;
    GltfLimits limits;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "convert",
      "Read a glTF model and write it back as restitch writes (world space, one mesh; .glb or .gltf by extension)");
  cmd->add_option("input", args->input, "input model (.glb or .gltf)")->required();
  cmd->add_option("-o,--output", args->output, "output model (.glb or .gltf)")->required()->check(gltf_output_path());
  add_limit_options(cmd, args->limits);
  cmd->callback([args, exit_code] {
    GltfLoadReport report;
    Result<Mesh> mesh = load_gltf(args->input, &report, args->limits);
    if (!mesh) {
      *exit_code = fail(mesh.status());
      return;
    }
    for (const std::string& w : report.warnings) std::fprintf(stderr, "restitch: warning: %s\n", w.c_str());
    if (Status s = save_gltf(*mesh, args->output); !s) {
      *exit_code = fail(s, true);
      return;
    }
    std::printf("wrote %s: %zu vertices, %zu triangles\n", args->output.c_str(), mesh->vertex_count(),
                mesh->triangle_count());
    *exit_code = exit_ok;
  });
}

}  // namespace restitch::cli

// restitch/io/gltf.hpp - glTF 2.0 in and out, losing nothing a resize can carry.
//
// Reading (`load_gltf`, `load_gltf_from_memory`): .glb or .gltf (embedded,
// data-URI or external buffers and images). Every triangle primitive of the
// default scene is flattened into one restitch::Mesh in world space (node
// transforms applied: positions by the matrix, normals by its inverse
// transpose, tangents by its linear part; a mirroring transform flips the
// winding back). Indexed or not; modes TRIANGLES, TRIANGLE_STRIP and
// TRIANGLE_FAN; any accessor component type (normalized integers too, as in
// KHR_mesh_quantization) and sparse accessors. Primitives with the same
// material and the same attribute set become one group.
// Materials, textures, images, samplers and their extensions pass through
// unchanged (`Mesh::assets`): image bytes are kept as they are, never decoded.
//
// What restitch cannot carry is reported, never dropped silently: skins,
// morph targets, animations, cameras, POINTS and LINES primitives, vertex
// colour sets past COLOR_0 and custom attributes produce a warning that
// names what was dropped; a required extension restitch cannot decode
// (Draco, meshopt...) is an error.
//
// Bad input (missing file, a directory, wrong magic, truncated binary,
// broken JSON, an accessor or index out of range, NaN positions, no
// triangles in the default scene) gives a non-ok Status whose message names
// the problem. Counts past `GltfLimits` (vertices and triangles over the
// default scene, instances included) are refused (too_large) before their
// data is decoded, and every accessor is checked against the bytes that are
// there before it is read, so no count a file declares is allocated blindly.
//
// Writing (`save_gltf`, `save_glb_to_memory`): one mesh, one node, one scene;
// one primitive per group with exactly the attributes the group carries
// (float POSITION with min/max, NORMAL, TANGENT, TEXCOORD_n, COLOR_0; uint16
// or uint32 indices), and the pass-through assets (images stored in the
// binary buffer). `.glb` writes binary, `.gltf` writes JSON with the buffer as
// a data URI. The file is written to a temporary name in the same folder and
// renamed, so a failed save leaves no partial file. Output is deterministic.
//
// Each glTF mesh is decoded once, however many nodes instance it; every
// instance is then placed with its own world transform.
//
// tinygltf is compiled in ONE translation unit of the program: there,
// `#define RESTITCH_GLTF_IMPLEMENTATION` before including this header (as
// with stb). Everywhere else include it plainly.
//
// The implementation lives in io/detail/, included below: gltf_accessor.hpp
// (accessor decoding), gltf_scene.hpp (the scene walk into mesh instances),
// gltf_primitives.hpp (primitive decoding, placement, extension checks,
// materials and assets), gltf_reader.hpp (parsing and building the Mesh) and
// gltf_writer.hpp (building and serializing the output model).
//
// Cost: linear in the file size plus the instanced vertex count.
#pragma once

#ifndef TINYGLTF_NOEXCEPTION
#define TINYGLTF_NOEXCEPTION
#endif
#ifndef TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE
#endif
#ifndef TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#endif
#ifndef TINYGLTF_NO_INCLUDE_STB_IMAGE
#define TINYGLTF_NO_INCLUDE_STB_IMAGE
#endif
#ifndef TINYGLTF_NO_INCLUDE_STB_IMAGE_WRITE
#define TINYGLTF_NO_INCLUDE_STB_IMAGE_WRITE
#endif
#ifdef RESTITCH_GLTF_IMPLEMENTATION
#define TINYGLTF_IMPLEMENTATION
#endif
#include <tiny_gltf.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "restitch/detail/file.hpp"
#include "restitch/mesh.hpp"
#include "restitch/status.hpp"

namespace restitch {

/// The pass-through part of a glTF file (see mesh.hpp): its materials,
/// textures, images (raw encoded bytes in `Image::image`, `mimeType` set),
/// samplers, the asset's copyright, and the extensions they use.
struct GltfAssets {
  tinygltf::Model model;  // only materials, textures, images, samplers, extensionsUsed, asset are meaningful
};

/// What a load found besides the mesh.
struct GltfLoadReport {
  std::size_t meshes = 0;      ///< glTF meshes in the file
  std::size_t primitives = 0;  ///< triangle primitives instanced by the default scene
  std::size_t nodes = 0;       ///< nodes in the file
  std::size_t materials = 0;
  std::size_t textures = 0;
  std::size_t images = 0;
  std::vector<std::string> warnings;  ///< each names what was dropped and why
};

/// What a load accepts at most; a file past a limit is refused (StatusCode::too_large, naming the limit
/// and this option) before its data is decoded. Counted over the default scene, instances included.
/// Defaults: 10 million each, ten times the largest model the bench analyses (1M triangles); a model
/// at the limit takes about 1 GB to load and resize.
struct GltfLimits {
  std::size_t max_vertices = 10'000'000;
  std::size_t max_triangles = 10'000'000;
};

}  // namespace restitch

// The implementation parts: they need tinygltf configured and the types above.
#define RESTITCH_GLTF_PARTS
#include "restitch/io/detail/gltf_accessor.hpp"
#include "restitch/io/detail/gltf_primitives.hpp"
#include "restitch/io/detail/gltf_reader.hpp"
#include "restitch/io/detail/gltf_scene.hpp"
#include "restitch/io/detail/gltf_writer.hpp"

namespace restitch {

/// Loads a glTF model from bytes. `base_dir` is where external buffers and
/// images are looked up ("" = none may be external). Warnings go to `report`.
template <class = void>
Result<Mesh> load_gltf_from_memory(const std::uint8_t* data, std::size_t size, const std::string& base_dir = "",
                                          GltfLoadReport* report = nullptr, const GltfLimits& limits = {}) {
  return detail::guarded("load_gltf_from_memory", [&]() -> Result<Mesh> {
    GltfLoadReport local;
    GltfLoadReport& r = report ? *report : local;
    r = GltfLoadReport();
    tinygltf::Model model;
    RESTITCH_TRY(detail::parse_model(data, size, base_dir, detail::has_glb_magic(data, size), model, r));
    Mesh mesh;
    RESTITCH_TRY(detail::build_mesh(model, mesh, r, limits));
    return mesh;
  });
}

/// Loads a .glb or .gltf file (see the header comment for what is carried).
template <class = void>
Result<Mesh> load_gltf(const std::string& path, GltfLoadReport* report = nullptr,
                              const GltfLimits& limits = {}) {
  return detail::guarded("load_gltf", [&]() -> Result<Mesh> {
    std::vector<std::uint8_t> bytes;
    RESTITCH_TRY(detail::read_file(path, bytes));
    Result<Mesh> mesh = load_gltf_from_memory(bytes.data(), bytes.size(), detail::parent_dir(path), report, limits);
    if (!mesh) return Status(mesh.status().code(), path + ": " + mesh.status().message());
    return mesh;
  });
}

/// Encodes a mesh as .glb bytes (deterministic).
template <class = void>
Result<std::vector<std::uint8_t>> save_glb_to_memory(const Mesh& mesh) {
  return detail::guarded("save_glb_to_memory", [&]() -> Result<std::vector<std::uint8_t>> {
    tinygltf::Model m;
    RESTITCH_TRY(detail::build_model(mesh, m));
    std::vector<std::uint8_t> bytes;
    RESTITCH_TRY(detail::serialize(m, true, bytes));
    return bytes;
  });
}

/// Saves a mesh as .glb (binary) or .gltf (JSON, embedded buffer) by the
/// path's extension; any other extension is an invalid_argument. Written to
/// a temporary file beside `path`, then renamed over it.
template <class = void>
Status save_gltf(const Mesh& mesh, const std::string& path) {
  return detail::guarded("save_gltf", [&]() -> Status {
    const std::string ext = detail::lower_extension(path);
    if (ext != ".glb" && ext != ".gltf")
      return error(StatusCode::invalid_argument, path + ": the output must end in .glb or .gltf");
    tinygltf::Model m;
    RESTITCH_TRY(detail::build_model(mesh, m));
    std::vector<std::uint8_t> bytes;
    RESTITCH_TRY(detail::serialize(m, ext == ".glb", bytes));
    return detail::write_file_atomic(path, bytes.data(), bytes.size());
  });
}

}  // namespace restitch

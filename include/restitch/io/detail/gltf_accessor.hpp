// restitch/io/detail/gltf_accessor.hpp - glTF accessors decoded to doubles, every byte range checked.
//
// Part of restitch/io/gltf.hpp, which includes it after configuring and
// including tinygltf; do not include it on its own.
//
// `read_accessor` turns accessor `index` into `count x components` doubles:
// any component type (normalized integers mapped to [0,1] / [-1,1] per the
// glTF spec, as in KHR_mesh_quantization), byte strides, and sparse blocks
// applied over the dense data (or over zeros without a bufferView). Every
// index, count, offset and stride is checked against the buffers before a
// byte is read; a violation is a parse_error (an unsupported one for matrix
// accessors) naming the accessor and what it refers to. Never throws.
// Also here, as the bottom layer the reader and the writer share:
// `gltf_error` (a message prefixed with where it happened) and `sniff_mime`.
//
// Cost: linear in the accessor's count.
#pragma once

#ifndef RESTITCH_GLTF_PARTS
#error "include restitch/io/gltf.hpp, not its detail parts"
#endif

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "restitch/status.hpp"

namespace restitch::detail {

inline Status gltf_error(StatusCode code, const std::string& where, const std::string& what) {
  return error(code, where.empty() ? what : where + ": " + what);
}

// The MIME type of encoded image bytes by their magic ("" if unknown).
template <class = void>
std::string sniff_mime(const std::vector<unsigned char>& b) {
  auto starts = [&](const char* magic, std::size_t n, std::size_t at = 0) {
    return b.size() >= at + n && std::memcmp(b.data() + at, magic, n) == 0;
  };
  if (starts("\x89PNG", 4)) return "image/png";
  if (starts("\xFF\xD8\xFF", 3)) return "image/jpeg";
  if (starts("RIFF", 4) && starts("WEBP", 4, 8)) return "image/webp";
  if (starts("\xABKTX 20", 7)) return "image/ktx2";
  return "";
}

// A value of type T stored (unaligned, little-endian as the host) at `p`.
template <class T>
T load_unaligned(const unsigned char* p) {
  T v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

// One component at `p` as a double; normalized integers per the glTF spec.
template <class = void>
double decode_component(const unsigned char* p, int comp_type, bool normalized) {
  switch (comp_type) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return load_unaligned<float>(p);
    case TINYGLTF_COMPONENT_TYPE_DOUBLE: return load_unaligned<double>(p);
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      const double v = load_unaligned<std::int8_t>(p);
      return normalized ? std::max(v / 127.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
      const double v = load_unaligned<std::uint8_t>(p);
      return normalized ? v / 255.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      const double v = load_unaligned<std::int16_t>(p);
      return normalized ? std::max(v / 32767.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      const double v = load_unaligned<std::uint16_t>(p);
      return normalized ? v / 65535.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_INT: return load_unaligned<std::int32_t>(p);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: return load_unaligned<std::uint32_t>(p);
  }
  return 0.0;
}

// Locates `n` elements of `elem` bytes in bufferView `bv` at `offset` with
// `stride`: `base` points at the first one (nullptr when n == 0). `here`
// names the accessor in messages.
template <class = void>
Status locate_elements(const tinygltf::Model& m, const std::string& here, int bv, std::size_t offset,
                              std::size_t stride, std::size_t elem, std::size_t n, const unsigned char*& base) {
  if (bv < 0 || bv >= int(m.bufferViews.size()))
    return gltf_error(StatusCode::parse_error, here,
                      "refers to bufferView " + std::to_string(bv) + ", which does not exist");
  const tinygltf::BufferView& view = m.bufferViews[bv];
  if (view.buffer < 0 || view.buffer >= int(m.buffers.size()))
    return gltf_error(StatusCode::parse_error, here, "its bufferView refers to a buffer that does not exist");
  const tinygltf::Buffer& buf = m.buffers[view.buffer];
  if (n == 0) {
    base = nullptr;
    return {};
  }
  // In 64 bits: with a 32-bit size_t (WebAssembly) a declared count of 2^31 would wrap around.
  const std::uint64_t need = std::uint64_t(offset) + std::uint64_t(stride) * std::uint64_t(n - 1) + std::uint64_t(elem);
  if (std::uint64_t(view.byteOffset) + std::uint64_t(view.byteLength) > std::uint64_t(buf.data.size()) ||
      need > std::uint64_t(view.byteLength))
    return gltf_error(StatusCode::parse_error, here,
                      "reads past the end of its data (needs " + std::to_string(need) + " bytes of bufferView " +
                          std::to_string(bv) + ", which has " + std::to_string(view.byteLength) + "; buffer " +
                          std::to_string(view.buffer) + " holds " + std::to_string(buf.data.size()) + ")");
  base = buf.data.data() + view.byteOffset + offset;
  return {};
}

// Applies accessor `a`'s sparse block over `out` (count x components values).
template <class = void>
Status apply_sparse(const tinygltf::Model& m, const tinygltf::Accessor& a, const std::string& here,
                           int components, std::vector<double>& out) {
  const std::size_t count = a.count;
  const int csize = tinygltf::GetComponentSizeInBytes(a.componentType);
  const std::size_t elem = std::size_t(components) * csize;
  const std::size_t n = a.sparse.count;
  const int isize = tinygltf::GetComponentSizeInBytes(a.sparse.indices.componentType);
  if (isize <= 0 || n > count) return gltf_error(StatusCode::parse_error, here, "has a malformed sparse block");
  const unsigned char* ib = nullptr;
  const unsigned char* vb = nullptr;
  RESTITCH_TRY(locate_elements(m, here, a.sparse.indices.bufferView, a.sparse.indices.byteOffset, isize, isize, n, ib));
  RESTITCH_TRY(locate_elements(m, here, a.sparse.values.bufferView, a.sparse.values.byteOffset, elem, elem, n, vb));
  for (std::size_t s = 0; s < n; ++s) {
    const double idx = decode_component(ib + s * isize, a.sparse.indices.componentType, false);
    if (!(idx >= 0 && idx < double(count)))
      return gltf_error(StatusCode::parse_error, here, "has a sparse index out of range");
    for (int c = 0; c < components; ++c)
      out[std::size_t(idx) * components + c] =
          decode_component(vb + s * elem + std::size_t(c) * csize, a.componentType, a.normalized);
  }
  return {};
}

// Reads accessor `index` as doubles (count by components), normalized
// integers mapped to [0,1] / [-1,1] per the glTF spec, sparse values applied.
// `where` names the reader of the accessor in messages.
template <class = void>
Status read_accessor(const tinygltf::Model& m, int index, std::vector<double>& out, int& components,
                            const std::string& where) {
  if (index < 0 || index >= int(m.accessors.size()))
    return gltf_error(
        StatusCode::parse_error, where,
        "refers to accessor " + std::to_string(index) + ", but the file has " + std::to_string(m.accessors.size()));
  const tinygltf::Accessor& a = m.accessors[index];
  const std::string here = where + " (accessor " + std::to_string(index) + ")";
  components = tinygltf::GetNumComponentsInType(a.type);
  const int csize = tinygltf::GetComponentSizeInBytes(a.componentType);
  if (components <= 0 || csize <= 0) return gltf_error(StatusCode::parse_error, here, "has an unknown type");
  if (a.type == TINYGLTF_TYPE_MAT2 || a.type == TINYGLTF_TYPE_MAT3 || a.type == TINYGLTF_TYPE_MAT4)
    return gltf_error(StatusCode::unsupported, here, "is a matrix accessor, not a vertex attribute");
  const std::size_t count = a.count;
  if (count > (std::size_t(1) << 31)) return gltf_error(StatusCode::parse_error, here, "has an absurd count");
  // The data is located (and its size checked against the buffer) before anything is allocated: a
  // count the file cannot hold is refused, never allocated.
  const std::size_t elem = std::size_t(components) * csize;
  const unsigned char* base = nullptr;
  std::size_t stride = elem;
  if (a.bufferView >= 0) {
    const tinygltf::BufferView& view =
        m.bufferViews.size() > std::size_t(a.bufferView) ? m.bufferViews[a.bufferView] : tinygltf::BufferView();
    stride = view.byteStride ? view.byteStride : elem;
    RESTITCH_TRY(locate_elements(m, here, a.bufferView, a.byteOffset, stride, elem, count, base));
  }
  if (std::uint64_t(count) * std::uint64_t(components) > std::uint64_t(out.max_size()))
    return gltf_error(StatusCode::parse_error, here, "has a count too large for this machine");
  out.assign(count * components, 0.0);
  if (a.bufferView >= 0) {
    for (std::size_t i = 0; i < count; ++i)
      for (int c = 0; c < components; ++c)
        out[i * components + c] =
            decode_component(base + i * stride + std::size_t(c) * csize, a.componentType, a.normalized);
  }
  if (a.sparse.isSparse) RESTITCH_TRY(apply_sparse(m, a, here, components, out));
  return {};
}

}  // namespace restitch::detail

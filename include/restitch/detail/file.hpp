// restitch/detail/file.hpp - whole-file reads and atomic writes, without exceptions.
//
// write_file_atomic writes to a temporary file in the destination's folder
// and renames it over the destination only once every byte is written, so a
// failure never leaves a half-written output. Cost: one pass over the bytes.
#pragma once

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <system_error>
#include <vector>

#include "restitch/status.hpp"

namespace restitch::detail {

template <class = void>
std::string parent_dir(const std::string& path) {
  const std::size_t slash = path.find_last_of("/\\");
  return slash == std::string::npos ? std::string() : path.substr(0, slash);
}

template <class = void>
std::string lower_extension(const std::string& path) {
  const std::size_t dot = path.find_last_of('.');
  const std::size_t slash = path.find_last_of("/\\");
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot);
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

template <class = void>
Status read_file(const std::string& path, std::vector<std::uint8_t>& out) {
  std::error_code ec;
  const auto st = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(st)) return error(StatusCode::io_error, path + ": no such file");
  if (std::filesystem::is_directory(st)) return error(StatusCode::io_error, path + ": is a directory, not a file");
  // Closed however this returns (a failed allocation in `out` throws std::bad_alloc).
  const std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!f) return error(StatusCode::io_error, path + ": cannot open (" + std::strerror(errno) + ")");
  out.clear();
  unsigned char buf[1 << 16];
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, f.get())) > 0) out.insert(out.end(), buf, buf + n);
  const bool bad = std::ferror(f.get()) != 0;
  if (bad) return error(StatusCode::io_error, path + ": read error");
  return {};
}

template <class = void>
Status write_file_atomic(const std::string& path, const void* data, std::size_t size) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) return error(StatusCode::io_error, path + ": is a directory");
  const std::string tmp = path + ".restitch-tmp";
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) return error(StatusCode::io_error, path + ": cannot write (" + std::strerror(errno) + ")");
  const bool wrote = std::fwrite(data, 1, size, f) == size;
  const bool closed = std::fclose(f) == 0;
  if (!wrote || !closed) {
    std::remove(tmp.c_str());
    return error(StatusCode::io_error, path + ": write failed (disk full?)");
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::string why = std::strerror(errno);
    std::remove(tmp.c_str());
    return error(StatusCode::io_error, path + ": cannot rename the temporary file into place (" + why + ")");
  }
  return {};
}

}  // namespace restitch::detail

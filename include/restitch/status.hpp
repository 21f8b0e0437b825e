// restitch/status.hpp - the error model of every public call.
//
// restitch never throws across its API: the same code runs as WebAssembly,
// where exceptions are off. Every public entry point returns a `Status` (for
// calls that fill an out-parameter) or a `Result<T>` (a value or a Status).
// Where C++ exceptions are on, each entry point also runs its body under
// detail::guarded: an allocation that fails (std::bad_alloc, std::length_error)
// comes back as too_large ("<call>: out of memory"), anything else thrown (a
// bug, or a custom policy that throws) as internal; no exception escapes. With
// exceptions off (WebAssembly), a failed allocation aborts the module instead,
// and the web demo's worker replaces it (demo_web/src/worker.js).
// A Status carries a code a program can branch on and a message a user can
// act on ("accessor 3 reads past the end of buffer 0", not "error -3").
//
// Programmer errors (a violated precondition that no input can cause) are
// checked with RESTITCH_ASSERT, which carries a message and is active unless
// NDEBUG is defined.
#pragma once

#include <cassert>
#include <exception>
#include <new>
#include <stdexcept>
#include <string>
#include <utility>
#include <variant>

namespace restitch {

/// What went wrong, coarse enough to branch on. The message says the rest.
enum class StatusCode {
  ok = 0,
  invalid_argument,  ///< a parameter or request outside its documented range
  io_error,          ///< a file could not be opened, read, written or renamed
  parse_error,       ///< a file is not valid glTF (magic, JSON, accessors...)
  invalid_mesh,      ///< empty mesh, NaN coordinates, out-of-range indices
  unsupported,       ///< valid input that restitch cannot carry
  no_repetition,     ///< the model has no repeat to resize along
  too_large,         ///< the request exceeds a documented limit
  cancelled,         ///< a progress callback asked to stop
  internal,          ///< a bug: please report it
};

/// Human-readable name of a code ("parse_error").
template <class = void>
const char* to_string(StatusCode c) noexcept {
  switch (c) {
    case StatusCode::ok:
      return "ok";
    case StatusCode::invalid_argument:
      return "invalid_argument";
    case StatusCode::io_error:
      return "io_error";
    case StatusCode::parse_error:
      return "parse_error";
    case StatusCode::invalid_mesh:
      return "invalid_mesh";
    case StatusCode::unsupported:
      return "unsupported";
    case StatusCode::no_repetition:
      return "no_repetition";
    case StatusCode::too_large:
      return "too_large";
    case StatusCode::cancelled:
      return "cancelled";
    case StatusCode::internal:
      return "internal";
  }
  return "unknown";
}

/// The outcome of a call: ok, or a code with a message.
class Status {
 public:
  Status() = default;  ///< ok
  Status(StatusCode code, std::string message) : code_(code), message_(std::move(message)) {}

  static Status success() { return {}; }
  bool ok() const noexcept { return code_ == StatusCode::ok; }
  explicit operator bool() const noexcept { return ok(); }
  StatusCode code() const noexcept { return code_; }
  const std::string& message() const noexcept { return message_; }

 private:
  StatusCode code_ = StatusCode::ok;
  std::string message_;
};

inline Status error(StatusCode code, std::string message) { return Status(code, std::move(message)); }

/// A value or the Status that explains why there is none.
/// `Result<T> r = f(); if (!r) report(r.status()); use(*r);`
template <class T>
class Result {
 public:
  Result(T value) : v_(std::move(value)) {}        // NOLINT(implicit): return a value directly
  Result(Status status) : v_(std::move(status)) {  // NOLINT(implicit): return an error directly
    assert(!std::get<Status>(v_).ok() && "Result built from an ok Status carries no value");
  }

  bool ok() const noexcept { return std::holds_alternative<T>(v_); }
  explicit operator bool() const noexcept { return ok(); }

  /// The error; an ok Status when there is a value.
  Status status() const { return ok() ? Status() : std::get<Status>(v_); }

  T& value() & { return std::get<T>(v_); }
  const T& value() const& { return std::get<T>(v_); }
  T&& value() && { return std::get<T>(std::move(v_)); }
  T& operator*() & { return value(); }
  const T& operator*() const& { return value(); }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }

 private:
  std::variant<T, Status> v_;
};

namespace detail {

#if defined(__cpp_exceptions) || defined(__EXCEPTIONS)
inline constexpr bool exceptions_enabled = true;
#else
inline constexpr bool exceptions_enabled = false;
#endif

// The Status of an exception caught at an entry point. Building its message allocates; if that fails
// too (memory is still short), the Status carries the code alone.
template <class = void>
Status status_of_exception(StatusCode code, const char* call, const char* what) noexcept {
  try {
    return Status(code, std::string(call) + ": " + what);
  } catch (...) {
    return Status(code, std::string());
  }
}

/// Runs `body` (returning a Status or a Result<T>) and returns what it returns; an exception thrown
/// inside becomes the returned Status: std::bad_alloc and std::length_error (a request for more memory
/// than there is) too_large, anything else internal. `call` names the entry point in the message.
template <class F>
auto guarded(const char* call, F&& body) noexcept -> decltype(body()) {
#if defined(__cpp_exceptions) || defined(__EXCEPTIONS)
  try {
    return body();
  } catch (const std::bad_alloc&) {
    return status_of_exception(StatusCode::too_large, call,
                               "out of memory (the model or request needs more memory than is available)");
  } catch (const std::length_error&) {
    return status_of_exception(StatusCode::too_large, call, "out of memory (a size past what can be allocated)");
  } catch (const std::exception& e) {
    return status_of_exception(StatusCode::internal, call, e.what());
  } catch (...) {
    return status_of_exception(StatusCode::internal, call, "an unknown exception");
  }
#else
  return body();
#endif
}

}  // namespace detail

}  // namespace restitch

/// Checks a programmer's precondition, with a message. Not for input errors.
#define RESTITCH_ASSERT(cond, msg) assert((cond) && msg)

/// Returns the Status of `expr` from the enclosing function if it is not ok.
#define RESTITCH_TRY(expr)                     \
  do {                                         \
    ::restitch::Status restitch_s_ = (expr);   \
    if (!restitch_s_.ok()) return restitch_s_; \
  } while (0)

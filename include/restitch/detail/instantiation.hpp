// restitch/detail/instantiation.hpp - the compiled mode's switch (internal).
//
// RESTITCH_INSTANTIATE(declaration) follows each entry point the compiled mode compiles once (the end
// of analyze.hpp, retarget.hpp, runtime.hpp). It expands to
//   * nothing in the default header-only mode;
//   * `extern template declaration;` where RESTITCH_COMPILED is defined (the restitch::compiled CMake
//     target defines it for its users): the unit calls the instantiation compiled elsewhere instead of
//     instantiating it (the entry points' bodies are defined out of their classes, not inline, so the
//     compiler does not instantiate them to inline them either);
//   * `template declaration;` in the one unit that includes restitch/instantiate.hpp, which compiles
//     them.
// Either way the same template is compiled from the same source, so the results are the same.
#pragma once

#if defined(RESTITCH_INSTANTIATING)
#define RESTITCH_INSTANTIATE(...) template __VA_ARGS__;
#elif defined(RESTITCH_COMPILED)
#define RESTITCH_INSTANTIATE(...) extern template __VA_ARGS__;
#else
#define RESTITCH_INSTANTIATE(...)
#endif

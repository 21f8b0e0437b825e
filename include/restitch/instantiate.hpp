// restitch/instantiate.hpp - the compiled mode: include in exactly one .cpp to compile the library's
// entry points with the shipped policies there, once.
//
//   // restitch_compiled.cpp, compiled with RESTITCH_COMPILED defined like every other unit
//   #include <restitch/instantiate.hpp>
//
// Every unit of the program then defines RESTITCH_COMPILED and sees `extern template` declarations
// (restitch/detail/instantiation.hpp) for what this unit compiles: analyze() with every descriptor,
// matcher and detector runtime.hpp can name, promote_offsets() with the default policies, the
// Retargeter with both label spaces and the default solver and stitcher, and runtime.hpp's calls. The
// CMake target restitch::compiled is this unit as a static library (the option RESTITCH_BUILD_COMPILED);
// without CMake, compile a .cpp holding the include above with -DRESTITCH_COMPILED and link it.
// Other instantiations (a policy of your own) are compiled where they are used, as in header-only mode.
#pragma once

#ifndef RESTITCH_COMPILED
#error "restitch/instantiate.hpp: define RESTITCH_COMPILED for this unit and for every unit that uses restitch"
#endif
#define RESTITCH_INSTANTIATING
#include "restitch/restitch.hpp"
#include "restitch/runtime.hpp"

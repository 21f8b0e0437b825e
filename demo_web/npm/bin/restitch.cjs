#!/usr/bin/env node
// `npx restitch ...`: the restitch command-line tool, compiled to WebAssembly (cli/restitch.cjs, from the
// same sources as the native tool, with Emscripten's NODERAWFS so it reads and writes real files). The
// arguments and output bytes are the native tool's (docs: restitch --help); analysis runs on one thread.
require('../cli/restitch.cjs');

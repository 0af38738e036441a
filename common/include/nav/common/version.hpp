// SPDX-License-Identifier: MIT
// The navbench version, fixed at build time (cmake/version.cmake).
#pragma once

namespace nav {

/// What `git describe --always --dirty` said when navbench was built (e.g. "8d15315-dirty",
/// or "v0.2.0-3-g8d15315" once tagged), or the CMake project version ("0.1.0") when built
/// outside a git checkout.
const char* navbench_version();

}  // namespace nav

// SPDX-License-Identifier: MIT
// Writing a file whole or not at all: a temporary file beside it, then a rename.
#pragma once

#include <string>

#include "nav/common/result.hpp"

namespace nav::reports {

/// Writes text to path through "<path>.tmp-<pid>" and a rename, so that a reader never sees
/// it half-written; on failure the temporary file is removed. Returns path.
Result<std::string> write_file_atomically(const std::string& path, const std::string& text);

}  // namespace nav::reports

// SPDX-License-Identifier: MIT
// The source of nav_test_pch (tests/CMakeLists.txt), whose precompiled header every test
// program reuses. It has no code of its own.

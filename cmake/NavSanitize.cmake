# SPDX-License-Identifier: MIT
# NAV_SANITIZE=ON: every target of the folder is built with AddressSanitizer and
# UndefinedBehaviorSanitizer (GCC or clang); an undefined behaviour stops the program like a
# crash. `scripts/test --sanitize` builds such a folder (build-sanitize/) and runs the unit and
# integration tests in it.
# GCC's flow analysis under the sanitizers warns of uninitialized reads inside libstdc++'s
# std::regex and std::function that are not there (the plain build has none): not a finding.
add_compile_options(-fsanitize=address,undefined -fno-sanitize-recover=undefined
                    -fno-omit-frame-pointer
                    $<$<CXX_COMPILER_ID:GNU>:-Wno-maybe-uninitialized>)
add_link_options(-fsanitize=address,undefined)

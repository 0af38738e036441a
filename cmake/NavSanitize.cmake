# SPDX-License-Identifier: MIT
# NAV_SANITIZE=ON: every target of the folder is built with AddressSanitizer and
# UndefinedBehaviorSanitizer (GCC or clang); an undefined behaviour stops the program like a
# crash. `scripts/test --sanitize` builds such a folder (build-sanitize/) and runs the unit and
# integration tests in it.
add_compile_options(-fsanitize=address,undefined -fno-sanitize-recover=undefined
                    -fno-omit-frame-pointer)
add_link_options(-fsanitize=address,undefined)

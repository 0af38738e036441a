// SPDX-License-Identifier: MIT
#include "nav/reports/sha256.hpp"

#include <openssl/evp.h>

#include <array>
#include <cstdio>
#include <memory>

namespace nav::reports {
namespace {

struct ContextFree {
  void operator()(EVP_MD_CTX* c) const { EVP_MD_CTX_free(c); }
};
using Context = std::unique_ptr<EVP_MD_CTX, ContextFree>;

struct FileClose {
  void operator()(std::FILE* f) const { std::fclose(f); }
};

Context start() {
  Context c(EVP_MD_CTX_new());
  if (c && EVP_DigestInit_ex(c.get(), EVP_sha256(), nullptr) != 1) c.reset();
  return c;
}

using Digest = std::array<unsigned char, EVP_MAX_MD_SIZE>;

std::optional<std::string> finish(EVP_MD_CTX* c) {
  Digest md{};
  unsigned int n = 0;
  if (EVP_DigestFinal_ex(c, md.data(), &n) != 1) return std::nullopt;
  static constexpr char kHex[] = "0123456789abcdef";
  std::string hex;
  for (unsigned int i = 0; i < n; ++i) {
    hex += kHex[md[i] >> 4];
    hex += kHex[md[i] & 0x0F];
  }
  return hex;
}

}  // namespace

std::string sha256_hex(std::string_view bytes) {
  const Context c = start();
  if (!c || EVP_DigestUpdate(c.get(), bytes.data(), bytes.size()) != 1) return {};
  return finish(c.get()).value_or(std::string());
}

std::string sha256_base64(std::string_view bytes) {
  Digest md{};
  unsigned int n = 0;
  if (EVP_Digest(bytes.data(), bytes.size(), md.data(), &n, EVP_sha256(), nullptr) != 1) return {};
  std::array<unsigned char, 4 * ((EVP_MAX_MD_SIZE + 2) / 3) + 1> text{};
  const int length = EVP_EncodeBlock(text.data(), md.data(), static_cast<int>(n));
  return std::string(reinterpret_cast<const char*>(text.data()), static_cast<std::size_t>(length));
}

std::optional<std::string> sha256_file(const std::string& path) {
  const std::unique_ptr<std::FILE, FileClose> f(std::fopen(path.c_str(), "rb"));
  const Context c = start();
  if (!f || !c) return std::nullopt;
  std::array<char, 1 << 16> block{};
  for (;;) {
    const std::size_t n = std::fread(block.data(), 1, block.size(), f.get());
    if (n > 0 && EVP_DigestUpdate(c.get(), block.data(), n) != 1) return std::nullopt;
    if (n < block.size()) break;
  }
  if (std::ferror(f.get())) return std::nullopt;
  return finish(c.get());
}

}  // namespace nav::reports

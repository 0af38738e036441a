// SPDX-License-Identifier: MIT
// Text from files and processes in the bench's documents: UTF-8 repair, HTML and XML
// escaping, JSON that any byte survives, numbers in the reports' tables.
#include <gtest/gtest.h>

#include <string>

#include <nlohmann/json.hpp>

#include "html_text.hpp"
#include "nav/reports/json_text.hpp"
#include "nav/reports/text.hpp"

namespace nav::reports {
namespace {

const std::string kFffd = "\xEF\xBF\xBD";

TEST(FixedDecimals, AValueThatRoundsToZeroHasNoMinusSign) {
  EXPECT_EQ(detail::fixed(-3e-5), "0.000");
  EXPECT_EQ(detail::fixed(-0.0), "0.000");
  EXPECT_EQ(detail::fixed(-0.0004, 4), "-0.0004");
  EXPECT_EQ(detail::fixed(-0.135), "-0.135");
  EXPECT_EQ(detail::fixed(-1000.0002), "-1000.000");
  EXPECT_EQ(detail::fixed(2.5), "2.500");
  EXPECT_EQ(detail::fixed(std::nullopt), "\u2014");
}

TEST(ValidUtf8, ValidTextIsUnchanged) {
  for (const std::string s : {"", "plain ascii", "d\xC3\xA9j\xC3\xA0 vu", "\xE2\x80\x93 dash",
                              "\xF0\x9F\x9A\x80 rocket", "\xF4\x8F\xBF\xBF", "tab\tnl\n"}) {
    EXPECT_EQ(valid_utf8(s), s);
  }
}

TEST(ValidUtf8, EachIllFormedSubpartBecomesOneReplacement) {
  EXPECT_EQ(valid_utf8("a\xFF" "b"), "a" + kFffd + "b");
  EXPECT_EQ(valid_utf8("\x80\x80"), kFffd + kFffd);              // stray continuations
  EXPECT_EQ(valid_utf8("\xC0\xAF"), kFffd + kFffd);              // overlong '/'
  EXPECT_EQ(valid_utf8("\xED\xA0\x80"), kFffd + kFffd + kFffd);  // a surrogate
  EXPECT_EQ(valid_utf8("\xF4\x90\x80\x80"), kFffd + kFffd + kFffd + kFffd);  // > U+10FFFF
  EXPECT_EQ(valid_utf8("\xE2\x80"), kFffd);                      // truncated at the end
  EXPECT_EQ(valid_utf8("\xE2\x80x"), kFffd + "x");               // truncated, then text
  EXPECT_EQ(valid_utf8("\xF0\x9F\x9Ax"), kFffd + "x");
}

TEST(ValidUtf8, EveryByteStringComesOutValid) {
  // All two-byte strings: the output is valid, so repairing it again changes nothing.
  for (int a = 0; a < 256; ++a) {
    for (int b = 0; b < 256; b += 7) {
      const std::string s{static_cast<char>(a), static_cast<char>(b)};
      const std::string once = valid_utf8(s);
      ASSERT_EQ(valid_utf8(once), once) << a << ' ' << b;
    }
  }
}

TEST(FirstInvalidUtf8, PointsAtTheFirstByteValidUtf8WouldReplace) {
  EXPECT_EQ(first_invalid_utf8(""), std::nullopt);
  EXPECT_EQ(first_invalid_utf8("plain \xC2\xB0 deg \xE2\x82\xAC"), std::nullopt);
  EXPECT_EQ(first_invalid_utf8("ab\xFF"), 2u);
  EXPECT_EQ(first_invalid_utf8("caf\xC3\""), 3u);        // a lead byte cut short
  EXPECT_EQ(first_invalid_utf8("\xED\xA0\x80"), 0u);    // a surrogate
  EXPECT_EQ(first_invalid_utf8("ok\xC0\xAF"), 2u);       // an overlong '/'
  // Agrees with valid_utf8 on every short byte string: invalid exactly where it changes.
  for (int a = 0; a < 256; ++a) {
    for (int b = 0; b < 256; b += 7) {
      const std::string s{static_cast<char>(a), static_cast<char>(b)};
      EXPECT_EQ(first_invalid_utf8(s).has_value(), valid_utf8(s) != s) << a << " " << b;
    }
  }
}

TEST(HtmlEscape, MarkupBecomesText) {
  EXPECT_EQ(html_escape("<script>alert(1)</script>"), "&lt;script&gt;alert(1)&lt;/script&gt;");
  EXPECT_EQ(html_escape("a & \"b\" 'c'"), "a &amp; &quot;b&quot; &#39;c&#39;");
  EXPECT_EQ(html_escape("x\xFFy"), "x" + kFffd + "y");
}

TEST(XmlEscape, ForbiddenControlCharactersAreReplaced) {
  EXPECT_EQ(xml_escape("a\x01" "b\tc\n"), "a" + kFffd + "b\tc\n");
  EXPECT_EQ(xml_escape("<&>"), "&lt;&amp;&gt;");
}

TEST(DumpJson, InvalidUtf8DoesNotThrow) {
  nlohmann::json j = {{"label", std::string("bad \xFF\xFE byte")}};
  EXPECT_THROW(static_cast<void>(j.dump()), nlohmann::json::type_error);  // what it replaces
  std::string text;
  ASSERT_NO_THROW(text = dump_json(j));
  EXPECT_EQ(nlohmann::json::parse(text)["label"], "bad " + kFffd + kFffd + " byte");
  nlohmann::ordered_json o = {{"x", std::string("\xC3")}};
  EXPECT_EQ(nlohmann::json::parse(dump_json(o))["x"], kFffd);
}

TEST(JsonForScript, CannotCloseTheScriptElementAndParsesBack) {
  const nlohmann::json j = {{"title", "</script><script>alert(1)</script><!-- & -->"},
                            {"n", 1.5},
                            {"bad", std::string("\xFF")}};
  const std::string text = json_for_script(j);
  EXPECT_EQ(text.find('<'), std::string::npos);
  EXPECT_EQ(text.find('>'), std::string::npos);
  EXPECT_EQ(text.find('&'), std::string::npos);
  const auto back = nlohmann::json::parse(text);
  EXPECT_EQ(back["title"], j["title"]);
  EXPECT_EQ(back["n"], 1.5);
  EXPECT_EQ(back["bad"], kFffd);
}

}  // namespace
}  // namespace nav::reports

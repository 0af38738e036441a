// SPDX-License-Identifier: MIT
// DBC reader and signal codec (see dbc.hpp for the grammar subset and the bit numbering).
//
// The reader tokenises the whole text first (identifiers, numbers, strings, punctuation, each
// with line, column and whether it starts a line), then walks the statements. Statements
// ending in ';' may span lines (CM_ texts often do); BU_, BO_, SG_ and the receiver list end
// at the line's end, so the parser asks whether the next token starts a line.
#include "nav/protocols/dbc.hpp"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <set>
#include <sstream>
#include <utility>

#include "nav/common/ensure.hpp"

namespace nav::protocols::dbc {
namespace {

constexpr std::string_view kIndependentSignalsMessage = "VECTOR__INDEPENDENT_SIG_MSG";

// ---------------------------------------------------------------------------------------
// Tokens

enum class TokenKind { kIdentifier, kNumber, kString, kPunct, kEnd };

struct Token {
  TokenKind kind = TokenKind::kEnd;
  std::string text;          ///< identifier/number text, string contents, punctuation char
  std::size_t line = 1;      ///< 1-based
  std::size_t column = 1;    ///< 1-based, in bytes
  bool starts_line = false;  ///< first token on its line
};

bool is_ident_start(char c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || c == '_'; }
bool is_digit(char c) { return c >= '0' && c <= '9'; }
bool is_ident_char(char c) { return is_ident_start(c) || is_digit(c); }

std::string describe(const Token& t) {
  switch (t.kind) {
    case TokenKind::kEnd:
      return "end of file";
    case TokenKind::kString: {
      std::string shown = t.text.size() > 20 ? t.text.substr(0, 20) + "..." : t.text;
      std::replace_if(
          shown.begin(), shown.end(), [](char c) { return c == '\n' || c == '\r'; }, ' ');
      return "string \"" + shown + "\"";
    }
    default:
      return "'" + t.text + "'";
  }
}

class Tokenizer {
 public:
  Tokenizer(std::string_view text, std::string_view file) : text_(text), file_(file) {}

  Result<std::vector<Token>> run() {
    std::vector<Token> tokens;
    std::size_t last_line = 0;
    while (true) {
      skip_space();
      Token t;
      t.line = line_;
      t.column = column_;
      t.starts_line = line_ != last_line;
      last_line = line_;
      if (pos_ >= text_.size()) {
        tokens.push_back(std::move(t));
        return tokens;
      }
      const char c = text_[pos_];
      if (c == '"') {
        t.kind = TokenKind::kString;
        advance();
        bool closed = false;
        while (pos_ < text_.size()) {
          char d = text_[pos_];
          if (d == '"') {
            advance();
            closed = true;
            break;
          }
          if (d == '\\' && pos_ + 1 < text_.size() &&
              (text_[pos_ + 1] == '"' || text_[pos_ + 1] == '\\')) {
            advance();
            d = text_[pos_];
          }
          t.text.push_back(d);
          advance();
        }
        if (!closed) {
          return fail(ErrorCode::kParse,
                      std::string(file_) + ":" + std::to_string(t.line) + ":" +
                          std::to_string(t.column) +
                          ": expected '\"' closing this string, found end of file");
        }
      } else if (is_ident_start(c)) {
        t.kind = TokenKind::kIdentifier;
        while (pos_ < text_.size() && is_ident_char(text_[pos_])) take(t);
      } else if (is_digit(c) || ((c == '-' || c == '+' || c == '.') && pos_ + 1 < text_.size() &&
                                 (is_digit(text_[pos_ + 1]) || text_[pos_ + 1] == '.'))) {
        t.kind = TokenKind::kNumber;
        take(t);
        while (pos_ < text_.size()) {
          const char d = text_[pos_];
          const bool exponent_sign = (d == '-' || d == '+') && !t.text.empty() &&
                                     (t.text.back() == 'e' || t.text.back() == 'E');
          if (!is_digit(d) && d != '.' && d != 'e' && d != 'E' && !exponent_sign) break;
          take(t);
        }
      } else {
        t.kind = TokenKind::kPunct;
        take(t);
      }
      tokens.push_back(std::move(t));
    }
  }

 private:
  void advance() {
    if (text_[pos_] == '\n') {
      ++line_;
      column_ = 1;
    } else {
      ++column_;
    }
    ++pos_;
  }
  void take(Token& t) {
    t.text.push_back(text_[pos_]);
    advance();
  }
  void skip_space() {
    while (pos_ < text_.size() && (text_[pos_] == ' ' || text_[pos_] == '\t' ||
                                   text_[pos_] == '\r' || text_[pos_] == '\n')) {
      advance();
    }
  }

  std::string_view text_;
  std::string_view file_;
  std::size_t pos_ = 0;
  std::size_t line_ = 1;
  std::size_t column_ = 1;
};

// ---------------------------------------------------------------------------------------
// Parser

class Parser {
 public:
  Parser(std::vector<Token> tokens, std::string_view file)
      : tokens_(std::move(tokens)), file_(file) {}

  Result<Database> run() {
    while (peek().kind != TokenKind::kEnd) {
      const Token& t = peek();
      if (t.kind != TokenKind::kIdentifier) return error(t, "a section keyword (BO_, CM_, ...)");
      Result<void> r;
      if (t.text == "VERSION") {
        r = parse_version();
      } else if (t.text == "NS_") {
        r = skip_indented_block();
      } else if (t.text == "BS_") {
        r = skip_to_line_end();
      } else if (t.text == "BU_") {
        r = parse_nodes();
      } else if (t.text == "BO_") {
        r = parse_message();
      } else if (t.text == "SG_") {
        r = error(t, "a section keyword (SG_ lines belong right under a BO_ line)");
      } else if (t.text == "CM_") {
        r = parse_comment();
      } else if (t.text == "BA_DEF_") {
        r = parse_attribute_definition();
      } else if (t.text == "BA_DEF_DEF_") {
        r = parse_attribute_default();
      } else if (t.text == "BA_") {
        r = parse_attribute();
      } else if (t.text == "VAL_") {
        r = parse_value_descriptions();
      } else if (t.text == "SIG_VALTYPE_") {
        r = parse_value_type();
      } else if (t.text == "SG_MUL_VAL_") {
        r = error(t, "no SG_MUL_VAL_ (extended multiplexing is not supported)");
      } else {
        skip_statement();
      }
      if (!r) return tl::unexpected(r.error());
    }
    return std::move(db_);
  }

 private:
  // -- token helpers --------------------------------------------------------------------
  const Token& peek() const { return tokens_[pos_]; }
  const Token& next() {
    const Token& t = tokens_[pos_];
    if (t.kind != TokenKind::kEnd) ++pos_;
    return t;
  }
  bool at_punct(char c) const { return peek().kind == TokenKind::kPunct && peek().text[0] == c; }
  bool at_ident(std::string_view word) const {
    return peek().kind == TokenKind::kIdentifier && peek().text == word;
  }
  /// True when the next token is on a later line than the previous one (or is the end).
  bool at_line_end() const { return peek().kind == TokenKind::kEnd || peek().starts_line; }

  tl::unexpected<Error> error(const Token& t, const std::string& expected) const {
    return tl::unexpected<Error>(
        Error{ErrorCode::kParse, where(t) + ": expected " + expected + ", found " + describe(t)});
  }
  tl::unexpected<Error> semantic(const Token& t, const std::string& what) const {
    return tl::unexpected<Error>(Error{ErrorCode::kParse, where(t) + ": " + what});
  }
  std::string where(const Token& t) const {
    return std::string(file_) + ":" + std::to_string(t.line) + ":" + std::to_string(t.column);
  }

  Result<std::string> identifier(const std::string& what) {
    if (peek().kind != TokenKind::kIdentifier) return error(peek(), what);
    return next().text;
  }
  Result<std::string> string(const std::string& what) {
    if (peek().kind != TokenKind::kString) return error(peek(), what);
    return next().text;
  }
  Result<void> punct(char c) {
    if (!at_punct(c)) return error(peek(), std::string("'") + c + "'");
    next();
    return {};
  }
  Result<double> number(const std::string& what) {
    const Token& t = peek();
    if (t.kind != TokenKind::kNumber) return error(t, what);
    std::string_view s = t.text;
    if (!s.empty() && s.front() == '+') s.remove_prefix(1);
    double v = 0.0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc{} || end != s.data() + s.size() || !std::isfinite(v)) return error(t, what);
    next();
    return v;
  }
  Result<std::int64_t> integer(const std::string& what) {
    const Token& t = peek();
    if (t.kind != TokenKind::kNumber) return error(t, what);
    std::string_view s = t.text;
    if (!s.empty() && s.front() == '+') s.remove_prefix(1);
    std::int64_t v = 0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc{} || end != s.data() + s.size()) return error(t, what);
    next();
    return v;
  }
  Result<std::uint32_t> unsigned32(const std::string& what) {
    const Token& t = peek();
    const auto v = integer(what);
    if (!v) return tl::unexpected(v.error());
    if (*v < 0 || *v > std::numeric_limits<std::uint32_t>::max()) return error(t, what);
    return static_cast<std::uint32_t>(*v);
  }

  /// Skips an unknown statement: through its ';', or up to the next line that starts in
  /// column 1 (a statement without ';').
  void skip_statement() {
    next();
    while (peek().kind != TokenKind::kEnd) {
      if (peek().starts_line && peek().column == 1) return;
      if (next().kind == TokenKind::kPunct && tokens_[pos_ - 1].text == ";") return;
    }
  }
  /// NS_ : and the indented names under it.
  Result<void> skip_indented_block() {
    next();
    if (auto r = punct(':'); !r) return r;
    while (peek().kind != TokenKind::kEnd && !(peek().starts_line && peek().column == 1)) next();
    return {};
  }
  Result<void> skip_to_line_end() {
    next();
    while (!at_line_end()) next();
    return {};
  }

  // -- references ---------------------------------------------------------------------
  struct MessageRef {
    Message* message = nullptr;  ///< nullptr: the dropped pseudo message
  };
  Result<MessageRef> message_ref() {
    const Token& t = peek();
    const auto raw = unsigned32("a message id");
    if (!raw) return tl::unexpected(raw.error());
    if (dropped_ids_.count(*raw) != 0) return MessageRef{};
    for (Message& m : db_.messages) {
      if ((m.extended ? (m.id | kExtendedIdFlag) : m.id) == *raw) return MessageRef{&m};
    }
    return error(t, "the id of a message defined by BO_");
  }
  /// A signal of a referenced message (nullptr when the message was dropped).
  Result<Signal*> signal_ref(const MessageRef& ref) {
    const Token& t = peek();
    const auto name = identifier("a signal name");
    if (!name) return tl::unexpected(name.error());
    if (ref.message == nullptr) return nullptr;
    for (Signal& s : ref.message->signals) {
      if (s.name == *name) return &s;
    }
    return error(t, "a signal of message '" + ref.message->name + "'");
  }
  Result<Node*> node_ref() {
    const Token& t = peek();
    const auto name = identifier("a node name");
    if (!name) return tl::unexpected(name.error());
    for (Node& n : db_.nodes) {
      if (n.name == *name) return &n;
    }
    return error(t, "a node listed in BU_");
  }

  // -- statements ---------------------------------------------------------------------
  Result<void> parse_version() {
    next();
    auto v = string("the version string");
    if (!v) return tl::unexpected(v.error());
    db_.version = std::move(*v);
    return {};
  }

  Result<void> parse_nodes() {
    next();
    if (auto r = punct(':'); !r) return r;
    while (!at_line_end()) {
      const Token& t = peek();
      auto name = identifier("a node name");
      if (!name) return tl::unexpected(name.error());
      if (std::any_of(db_.nodes.begin(), db_.nodes.end(),
                      [&](const Node& n) { return n.name == *name; })) {
        return semantic(t, "expected a new node name, '" + *name + "' is listed twice");
      }
      db_.nodes.push_back(Node{std::move(*name), {}, {}});
    }
    return {};
  }

  Result<void> parse_message() {
    next();
    const Token& id_token = peek();
    const auto raw = unsigned32("a message id");
    if (!raw) return tl::unexpected(raw.error());
    Message m;
    m.extended = (*raw & kExtendedIdFlag) != 0;
    m.id = *raw & ~kExtendedIdFlag;
    auto name = identifier("a message name");
    if (!name) return tl::unexpected(name.error());
    m.name = std::move(*name);
    const bool dropped = m.name == kIndependentSignalsMessage;
    if (!dropped && m.id > (m.extended ? kMaxExtendedId : kMaxStandardId)) {
      return semantic(id_token, m.extended ? "expected a 29-bit id with bit 31 set"
                                           : "expected an 11-bit id (set bit 31 for 29-bit ids)");
    }
    if (auto r = punct(':'); !r) return r;
    const Token& dlc_token = peek();
    const auto dlc = unsigned32("the data length [bytes]");
    if (!dlc) return tl::unexpected(dlc.error());
    if (*dlc > kMaxDataBytes) return error(dlc_token, "a data length of 0..64 bytes");
    m.dlc = *dlc;
    auto transmitter = identifier("the transmitting node");
    if (!transmitter) return tl::unexpected(transmitter.error());
    m.transmitter = std::move(*transmitter);
    if (!at_line_end()) return error(peek(), "the end of the BO_ line");

    const Token* multiplexor = nullptr;
    const Token* first_multiplexed = nullptr;
    while (at_ident("SG_")) {
      const Token& sg_token = peek();
      auto s = parse_signal(m);
      if (!s) return tl::unexpected(s.error());
      if (s->mux_role == MuxRole::kMultiplexor) {
        if (multiplexor != nullptr) {
          return semantic(sg_token,
                          "expected one multiplexor (M) per message, found a second "
                          "(extended multiplexing is not supported)");
        }
        multiplexor = &sg_token;
      }
      if (s->mux_role == MuxRole::kMultiplexed && first_multiplexed == nullptr) {
        first_multiplexed = &sg_token;
      }
      m.signals.push_back(std::move(*s));
    }
    if (first_multiplexed != nullptr && multiplexor == nullptr) {
      return semantic(*first_multiplexed, "expected a multiplexor signal (M) in message '" +
                                              m.name + "' for this multiplexed signal");
    }
    if (dropped) {
      dropped_ids_.insert(*raw);
      return {};
    }
    for (const Message& other : db_.messages) {
      if (other.id == m.id && other.extended == m.extended) {
        return semantic(id_token,
                        "expected a new message id, message '" + other.name + "' has the same one");
      }
      if (other.name == m.name) {
        return semantic(id_token, "expected a new message name, '" + m.name + "' is defined twice");
      }
    }
    db_.messages.push_back(std::move(m));
    return {};
  }

  Result<Signal> parse_signal(const Message& m) {
    next();  // SG_
    Signal s;
    const Token& name_token = peek();
    auto name = identifier("a signal name");
    if (!name) return tl::unexpected(name.error());
    s.name = std::move(*name);
    if (m.find_signal(s.name) != nullptr) {
      return semantic(name_token, "expected a new signal name, '" + s.name +
                                      "' appears twice in '" + m.name + "'");
    }
    if (peek().kind == TokenKind::kIdentifier) {
      const Token& mux = next();
      const std::string& x = mux.text;
      const bool digits = x.size() > 1 && std::all_of(x.begin() + 1, x.end(), is_digit);
      if (x == "M") {
        s.mux_role = MuxRole::kMultiplexor;
      } else if (x[0] == 'm' && digits && x.size() <= 10) {
        s.mux_role = MuxRole::kMultiplexed;
        s.mux_value = static_cast<std::uint32_t>(std::stoul(x.substr(1)));
      } else if (x[0] == 'm' && x.back() == 'M') {
        return semantic(mux,
                        "expected M or m<n>: extended multiplexing ('" + x + "') is not supported");
      } else {
        return error(mux, "a multiplexer indicator (M or m<n>) or ':'");
      }
    }
    if (auto r = punct(':'); !r) return tl::unexpected(r.error());
    const Token& start_token = peek();
    const auto start = unsigned32("the start bit");
    if (!start) return tl::unexpected(start.error());
    s.start_bit = *start;
    if (auto r = punct('|'); !r) return tl::unexpected(r.error());
    const Token& length_token = peek();
    const auto length = unsigned32("the length [bits]");
    if (!length) return tl::unexpected(length.error());
    if (*length < 1 || *length > 64) return error(length_token, "a length of 1..64 bits");
    s.length = *length;
    if (auto r = punct('@'); !r) return tl::unexpected(r.error());
    const Token& order_token = peek();
    const auto order = integer("the byte order 0 (Motorola) or 1 (Intel)");
    if (!order) return tl::unexpected(order.error());
    if (*order != 0 && *order != 1)
      return error(order_token, "the byte order 0 (Motorola) or 1 (Intel)");
    s.byte_order = *order == 1 ? ByteOrder::kIntel : ByteOrder::kMotorola;
    if (!at_punct('+') && !at_punct('-')) return error(peek(), "'+' (unsigned) or '-' (signed)");
    s.is_signed = next().text == "-";
    if (auto r = punct('('); !r) return tl::unexpected(r.error());
    const Token& factor_token = peek();
    const auto factor = number("the factor");
    if (!factor) return tl::unexpected(factor.error());
    if (*factor == 0.0) return error(factor_token, "a non-zero factor");
    s.factor = *factor;
    if (auto r = punct(','); !r) return tl::unexpected(r.error());
    const auto offset = number("the offset");
    if (!offset) return tl::unexpected(offset.error());
    s.offset = *offset;
    if (auto r = punct(')'); !r) return tl::unexpected(r.error());
    if (auto r = punct('['); !r) return tl::unexpected(r.error());
    const auto minimum = number("the minimum");
    if (!minimum) return tl::unexpected(minimum.error());
    if (auto r = punct('|'); !r) return tl::unexpected(r.error());
    const auto maximum = number("the maximum");
    if (!maximum) return tl::unexpected(maximum.error());
    if (auto r = punct(']'); !r) return tl::unexpected(r.error());
    s.minimum = *minimum;
    s.maximum = *maximum;
    auto unit = string("the unit string");
    if (!unit) return tl::unexpected(unit.error());
    s.unit = std::move(*unit);
    while (!at_line_end()) {
      if (at_punct(',')) {
        next();
        continue;
      }
      auto receiver = identifier("a receiving node");
      if (!receiver) return tl::unexpected(receiver.error());
      s.receivers.push_back(std::move(*receiver));
    }
    if (m.name != kIndependentSignalsMessage && !fits(s, m.dlc)) {
      return semantic(start_token, "expected signal '" + s.name + "' to fit in the " +
                                       std::to_string(m.dlc) + " data bytes of '" + m.name + "'");
    }
    return s;
  }

  Result<void> parse_comment() {
    next();
    std::string* target = nullptr;
    std::string ignored;
    if (at_ident("BU_")) {
      next();
      auto n = node_ref();
      if (!n) return tl::unexpected(n.error());
      target = &(*n)->comment;
    } else if (at_ident("BO_")) {
      next();
      auto m = message_ref();
      if (!m) return tl::unexpected(m.error());
      target = m->message != nullptr ? &m->message->comment : &ignored;
    } else if (at_ident("SG_")) {
      next();
      auto m = message_ref();
      if (!m) return tl::unexpected(m.error());
      auto s = signal_ref(*m);
      if (!s) return tl::unexpected(s.error());
      target = *s != nullptr ? &(*s)->comment : &ignored;
    } else if (at_ident("EV_")) {
      next();
      auto ev = identifier("an environment variable name");
      if (!ev) return tl::unexpected(ev.error());
      target = &ignored;
    } else if (peek().kind == TokenKind::kString) {
      target = &db_.comment;
    } else {
      return error(peek(), "BU_, BO_, SG_, EV_ or the comment string");
    }
    auto text = string("the comment string");
    if (!text) return tl::unexpected(text.error());
    *target = std::move(*text);
    return punct(';');
  }

  Result<void> parse_attribute_definition() {
    next();
    AttributeDefinition d;
    if (peek().kind == TokenKind::kIdentifier) {
      const Token& t = next();
      if (t.text == "BU_") {
        d.object = AttributeObject::kNode;
      } else if (t.text == "BO_") {
        d.object = AttributeObject::kMessage;
      } else if (t.text == "SG_") {
        d.object = AttributeObject::kSignal;
      } else if (t.text == "EV_") {
        d.object = AttributeObject::kEnvironmentVariable;
      } else {
        return error(t, "BU_, BO_, SG_, EV_ or the attribute name");
      }
    }
    auto name = string("the attribute name string");
    if (!name) return tl::unexpected(name.error());
    d.name = std::move(*name);
    const Token& type_token = peek();
    auto type = identifier("an attribute type (INT, HEX, FLOAT, STRING, ENUM)");
    if (!type) return tl::unexpected(type.error());
    if (*type == "INT" || *type == "HEX" || *type == "FLOAT") {
      d.type = *type == "INT" ? AttributeType::kInt
                              : (*type == "HEX" ? AttributeType::kHex : AttributeType::kFloat);
      const auto lo = number("the minimum");
      if (!lo) return tl::unexpected(lo.error());
      const auto hi = number("the maximum");
      if (!hi) return tl::unexpected(hi.error());
      d.minimum = *lo;
      d.maximum = *hi;
    } else if (*type == "STRING") {
      d.type = AttributeType::kString;
    } else if (*type == "ENUM") {
      d.type = AttributeType::kEnum;
      while (!at_punct(';')) {
        auto label = string("an ENUM label string");
        if (!label) return tl::unexpected(label.error());
        d.enum_values.push_back(std::move(*label));
        if (at_punct(',')) next();
      }
    } else {
      return error(type_token, "an attribute type (INT, HEX, FLOAT, STRING, ENUM)");
    }
    if (auto r = punct(';'); !r) return r;
    const std::string key = d.name;
    db_.attribute_definitions[key] = std::move(d);
    return {};
  }

  /// An attribute value checked against its definition.
  Result<AttributeValue> attribute_value(const AttributeDefinition& d) {
    const Token& t = peek();
    if (d.type == AttributeType::kString) {
      auto s = string("a string value for attribute '" + d.name + "'");
      if (!s) return tl::unexpected(s.error());
      return AttributeValue{std::move(*s)};
    }
    if (d.type == AttributeType::kEnum && t.kind == TokenKind::kString) {
      if (std::find(d.enum_values.begin(), d.enum_values.end(), t.text) == d.enum_values.end()) {
        return error(t, "one of the ENUM labels of attribute '" + d.name + "'");
      }
      return AttributeValue{next().text};
    }
    const auto v = number("a number for attribute '" + d.name + "'");
    if (!v) return tl::unexpected(v.error());
    const bool integral = d.type != AttributeType::kFloat;
    const double hi =
        d.type == AttributeType::kEnum ? static_cast<double>(d.enum_values.size()) - 1 : d.maximum;
    const double lo = d.type == AttributeType::kEnum ? 0.0 : d.minimum;
    const bool ranged = d.type == AttributeType::kEnum || lo != 0.0 || hi != 0.0;
    if ((integral && std::floor(*v) != *v) || (ranged && (*v < lo || *v > hi))) {
      std::ostringstream what;
      what << (integral ? "an integer" : "a number") << " in [" << lo << ", " << hi
           << "] for attribute '" << d.name << "'";
      return tl::unexpected<Error>(Error{
          ErrorCode::kParse, where(t) + ": expected " + what.str() + ", found " + describe(t)});
    }
    return AttributeValue{*v};
  }

  Result<const AttributeDefinition*> definition_of(const Token& t, const std::string& name) {
    const auto it = db_.attribute_definitions.find(name);
    if (it == db_.attribute_definitions.end()) return error(t, "an attribute defined by BA_DEF_");
    return &it->second;
  }

  Result<void> parse_attribute_default() {
    next();
    const Token& name_token = peek();
    auto name = string("the attribute name string");
    if (!name) return tl::unexpected(name.error());
    auto d = definition_of(name_token, *name);
    if (!d) return tl::unexpected(d.error());
    auto v = attribute_value(**d);
    if (!v) return tl::unexpected(v.error());
    db_.attribute_definitions[*name].default_value = std::move(*v);
    return punct(';');
  }

  Result<void> parse_attribute() {
    next();
    const Token& name_token = peek();
    auto name = string("the attribute name string");
    if (!name) return tl::unexpected(name.error());
    auto d = definition_of(name_token, *name);
    if (!d) return tl::unexpected(d.error());
    Attributes* target = &db_.attributes;
    Attributes ignored;
    AttributeObject object = AttributeObject::kNetwork;
    const Token& object_token = peek();
    if (at_ident("BU_")) {
      next();
      object = AttributeObject::kNode;
      auto n = node_ref();
      if (!n) return tl::unexpected(n.error());
      target = &(*n)->attributes;
    } else if (at_ident("BO_")) {
      next();
      object = AttributeObject::kMessage;
      auto m = message_ref();
      if (!m) return tl::unexpected(m.error());
      target = m->message != nullptr ? &m->message->attributes : &ignored;
    } else if (at_ident("SG_")) {
      next();
      object = AttributeObject::kSignal;
      auto m = message_ref();
      if (!m) return tl::unexpected(m.error());
      auto s = signal_ref(*m);
      if (!s) return tl::unexpected(s.error());
      target = *s != nullptr ? &(*s)->attributes : &ignored;
    } else if (at_ident("EV_")) {
      next();
      object = AttributeObject::kEnvironmentVariable;
      auto ev = identifier("an environment variable name");
      if (!ev) return tl::unexpected(ev.error());
      target = &ignored;
    }
    if (object != (*d)->object) {
      static constexpr const char* kObjectNames[] = {"the network", "a node (BU_)",
                                                     "a message (BO_)", "a signal (SG_)",
                                                     "an environment variable (EV_)"};
      return semantic(object_token, "expected attribute '" + *name + "' on " +
                                        kObjectNames[static_cast<int>((*d)->object)] +
                                        " as BA_DEF_ defines it");
    }
    auto v = attribute_value(**d);
    if (!v) return tl::unexpected(v.error());
    (*target)[*name] = std::move(*v);
    return punct(';');
  }

  Result<void> parse_value_descriptions() {
    next();
    if (peek().kind == TokenKind::kIdentifier) {  // VAL_ of an environment variable
      --pos_;
      skip_statement();
      return {};
    }
    auto m = message_ref();
    if (!m) return tl::unexpected(m.error());
    auto s = signal_ref(*m);
    if (!s) return tl::unexpected(s.error());
    std::map<std::int64_t, std::string> table;
    while (!at_punct(';')) {
      const auto value = integer("an integer raw value or ';'");
      if (!value) return tl::unexpected(value.error());
      auto text = string("the value's description string");
      if (!text) return tl::unexpected(text.error());
      table[*value] = std::move(*text);
    }
    next();
    if (*s != nullptr) (*s)->value_descriptions = std::move(table);
    return {};
  }

  Result<void> parse_value_type() {
    next();
    auto m = message_ref();
    if (!m) return tl::unexpected(m.error());
    const Token& signal_token = peek();
    auto s = signal_ref(*m);
    if (!s) return tl::unexpected(s.error());
    if (at_punct(':')) next();  // "SIG_VALTYPE_ id name : 1;" (the colon is optional in the wild)
    const Token& type_token = peek();
    const auto type = integer("the value type 0 (integer), 1 (float) or 2 (double)");
    if (!type) return tl::unexpected(type.error());
    if (*type < 0 || *type > 2)
      return error(type_token, "the value type 0 (integer), 1 (float) or 2 (double)");
    if (*s != nullptr) {
      const std::uint32_t need = *type == 1 ? 32 : 64;
      if (*type != 0 && (*s)->length != need) {
        return semantic(signal_token, "expected signal '" + (*s)->name + "' to be " +
                                          std::to_string(need) + " bits long for value type " +
                                          std::to_string(*type));
      }
      (*s)->value_type = *type == 0 ? ValueType::kInteger
                                    : (*type == 1 ? ValueType::kFloat32 : ValueType::kFloat64);
    }
    return punct(';');
  }

  std::vector<Token> tokens_;
  std::string_view file_;
  std::size_t pos_ = 0;
  Database db_;
  std::set<std::uint32_t> dropped_ids_;  ///< raw BO_ ids of VECTOR__INDEPENDENT_SIG_MSG
};

// ---------------------------------------------------------------------------------------
// Bits

/// Visits the signal's bit positions from its LSB (raw bit 0) upwards: f(raw_bit, position).
template <typename F>
void for_each_bit(const Signal& s, F&& f) {
  if (s.byte_order == ByteOrder::kIntel) {
    for (std::uint32_t k = 0; k < s.length; ++k) f(k, std::uint64_t{s.start_bit} + k);
    return;
  }
  // Motorola: walk from the MSB (the start bit) down, wrapping to bit 7 of the next byte.
  std::uint64_t position = s.start_bit;
  for (std::uint32_t k = 0; k < s.length; ++k) {
    f(s.length - 1 - k, position);
    position = position % 8 == 0 ? position + 15 : position - 1;
  }
}

double bound_tolerance(double bound) { return 1e-9 * std::max(1.0, std::fabs(bound)); }

std::string format_number(double v) {
  std::ostringstream os;
  os.precision(12);
  os << v;
  return os.str();
}

}  // namespace

// ---------------------------------------------------------------------------------------
// Database lookups

const Signal* Message::find_signal(std::string_view signal_name) const {
  for (const Signal& s : signals) {
    if (s.name == signal_name) return &s;
  }
  return nullptr;
}

const Message* Database::find_message(std::string_view message_name) const {
  for (const Message& m : messages) {
    if (m.name == message_name) return &m;
  }
  return nullptr;
}

const Message* Database::find_message(std::uint32_t id, bool extended) const {
  for (const Message& m : messages) {
    if (m.id == id && m.extended == extended) return &m;
  }
  return nullptr;
}

std::optional<AttributeValue> Database::attribute(const Message& m, std::string_view name) const {
  if (const auto it = m.attributes.find(name); it != m.attributes.end()) return it->second;
  const auto d = attribute_definitions.find(name);
  if (d == attribute_definitions.end() || d->second.object != AttributeObject::kMessage) {
    return std::nullopt;
  }
  return d->second.default_value;
}

std::optional<double> Database::number_attribute(const Message& m, std::string_view name) const {
  const auto v = attribute(m, name);
  if (!v) return std::nullopt;
  if (const double* x = std::get_if<double>(&*v)) return *x;
  const auto d = attribute_definitions.find(name);
  if (d == attribute_definitions.end() || d->second.type != AttributeType::kEnum)
    return std::nullopt;
  const auto& labels = d->second.enum_values;
  const auto it = std::find(labels.begin(), labels.end(), std::get<std::string>(*v));
  if (it == labels.end()) return std::nullopt;
  return static_cast<double>(it - labels.begin());
}

std::optional<std::chrono::milliseconds> Database::cycle_time(const Message& m) const {
  const auto v = number_attribute(m, kCycleTimeAttribute);
  if (!v || *v <= 0.0) return std::nullopt;
  return std::chrono::milliseconds{static_cast<std::int64_t>(std::llround(*v))};
}

// ---------------------------------------------------------------------------------------
// Reading

Result<Database> parse(std::string_view text, std::string_view file) {
  auto tokens = Tokenizer(text, file).run();
  if (!tokens) return tl::unexpected(tokens.error());
  return Parser(std::move(*tokens), file).run();
}

Result<Database> load(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return fail(ErrorCode::kNotFound, path.string() + ": cannot open the DBC file");
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  return parse(text, path.string());
}

// ---------------------------------------------------------------------------------------
// Codec

bool fits(const Signal& s, std::size_t bytes) {
  bool ok = true;
  for_each_bit(s, [&](std::uint32_t, std::uint64_t position) {
    if (position / 8 >= bytes) ok = false;
  });
  return ok;
}

Result<std::uint64_t> get_raw(const Signal& s, ByteSpan data) {
  if (!fits(s, data.size())) {
    return fail(ErrorCode::kInvalidArgument, "signal '" + s.name + "' does not fit in " +
                                                 std::to_string(data.size()) + " data bytes");
  }
  std::uint64_t raw = 0;
  for_each_bit(s, [&](std::uint32_t bit, std::uint64_t position) {
    const auto byte = data[static_cast<std::size_t>(position / 8)];
    raw |= static_cast<std::uint64_t>((byte >> (position % 8)) & 1u) << bit;
  });
  return raw;
}

void put_raw(const Signal& s, std::uint64_t raw, std::span<std::uint8_t> data) {
  NAV_ENSURE(fits(s, data.size()), "signal '" + s.name + "' does not fit the data");
  NAV_ENSURE(s.length == 64 || (raw >> s.length) == 0, "raw value wider than signal " + s.name);
  for_each_bit(s, [&](std::uint32_t bit, std::uint64_t position) {
    auto& byte = data[static_cast<std::size_t>(position / 8)];
    const auto mask = static_cast<std::uint8_t>(1u << (position % 8));
    byte = ((raw >> bit) & 1u) != 0 ? static_cast<std::uint8_t>(byte | mask)
                                    : static_cast<std::uint8_t>(byte & ~mask);
  });
}

Result<double> decode(const Signal& s, ByteSpan data) {
  const auto raw = get_raw(s, data);
  if (!raw) return tl::unexpected(raw.error());
  double value = 0.0;
  switch (s.value_type) {
    case ValueType::kFloat32:
      value = static_cast<double>(std::bit_cast<float>(static_cast<std::uint32_t>(*raw)));
      break;
    case ValueType::kFloat64:
      value = std::bit_cast<double>(*raw);
      break;
    case ValueType::kInteger:
      if (s.is_signed && s.length < 64 && ((*raw >> (s.length - 1)) & 1u) != 0) {
        value =
            static_cast<double>(static_cast<std::int64_t>(*raw | (~std::uint64_t{0} << s.length)));
      } else if (s.is_signed) {
        value = static_cast<double>(static_cast<std::int64_t>(*raw));
      } else {
        value = static_cast<double>(*raw);
      }
      break;
  }
  return value * s.factor + s.offset;
}

Result<void> encode(const Signal& s, double value, std::span<std::uint8_t> data) {
  const auto refuse = [&](const std::string& why) {
    return fail(ErrorCode::kInvalidArgument, "signal '" + s.name + "': " + why);
  };
  if (!fits(s, data.size()))
    return refuse("does not fit in " + std::to_string(data.size()) + " data bytes");
  if (std::isnan(value)) return refuse("value is NaN");
  const bool ranged = s.minimum != 0.0 || s.maximum != 0.0;
  if (ranged && (value < s.minimum - bound_tolerance(s.minimum) ||
                 value > s.maximum + bound_tolerance(s.maximum))) {
    return refuse(format_number(value) + " " + s.unit + " outside [" + format_number(s.minimum) +
                  ", " + format_number(s.maximum) + "]");
  }
  const double scaled = (value - s.offset) / s.factor;
  std::uint64_t raw = 0;
  switch (s.value_type) {
    case ValueType::kFloat32:
      raw = std::bit_cast<std::uint32_t>(static_cast<float>(scaled));
      break;
    case ValueType::kFloat64:
      raw = std::bit_cast<std::uint64_t>(scaled);
      break;
    case ValueType::kInteger: {
      const double r = std::round(scaled);
      const double lo = s.is_signed ? -std::ldexp(1.0, static_cast<int>(s.length) - 1) : 0.0;
      const double hi_exclusive =
          std::ldexp(1.0, static_cast<int>(s.length) - (s.is_signed ? 1 : 0));
      if (!(r >= lo && r < hi_exclusive)) {
        return refuse(format_number(value) + " " + s.unit + " needs raw " + format_number(r) +
                      ", beyond the " + std::to_string(s.length) + "-bit " +
                      (s.is_signed ? "signed" : "unsigned") + " field");
      }
      if (s.is_signed) {
        raw = static_cast<std::uint64_t>(static_cast<std::int64_t>(r));
        if (s.length < 64) raw &= (std::uint64_t{1} << s.length) - 1;
      } else {
        raw = static_cast<std::uint64_t>(r);
      }
      break;
    }
  }
  put_raw(s, raw, data);
  return {};
}

namespace {

/// Raw value of the message's multiplexor, nullopt when it has none.
Result<std::optional<std::uint64_t>> multiplexor_value(const Message& m, ByteSpan data) {
  for (const Signal& s : m.signals) {
    if (s.mux_role != MuxRole::kMultiplexor) continue;
    const auto raw = get_raw(s, data);
    if (!raw) return tl::unexpected(raw.error());
    return std::optional<std::uint64_t>{*raw};
  }
  return std::optional<std::uint64_t>{};
}

bool present(const Signal& s, const std::optional<std::uint64_t>& selector) {
  return s.mux_role != MuxRole::kMultiplexed || (selector && *selector == s.mux_value);
}

}  // namespace

Result<std::vector<SignalValue>> decode(const Message& m, ByteSpan data) {
  if (data.size() < m.dlc) {
    return fail(ErrorCode::kInvalidArgument, "message '" + m.name +
                                                 "': " + std::to_string(data.size()) +
                                                 " data bytes, DBC says " + std::to_string(m.dlc));
  }
  const auto selector = multiplexor_value(m, data);
  if (!selector) return tl::unexpected(selector.error());
  std::vector<SignalValue> out;
  for (const Signal& s : m.signals) {
    if (!present(s, *selector)) continue;
    const auto v = decode(s, data);
    if (!v) return tl::unexpected(v.error());
    out.push_back(SignalValue{&s, *v});
  }
  return out;
}

Result<Frame> encode(const Message& m, const std::map<std::string, double, std::less<>>& values) {
  for (const auto& [name, value] : values) {
    if (m.find_signal(name) == nullptr) {
      return fail(ErrorCode::kInvalidArgument,
                  "message '" + m.name + "' has no signal '" + name + "'");
    }
  }
  Frame f{m.id, m.extended, Bytes(m.dlc, 0)};
  // The multiplexor first: its value decides which multiplexed signals are present.
  std::vector<const Signal*> order;
  for (const Signal& s : m.signals) {
    if (s.mux_role == MuxRole::kMultiplexor)
      order.insert(order.begin(), &s);
    else
      order.push_back(&s);
  }
  std::optional<std::uint64_t> selector;
  for (const Signal* s : order) {
    if (!present(*s, selector)) continue;
    const auto it = values.find(s->name);
    if (it == values.end()) {
      return fail(ErrorCode::kInvalidArgument,
                  "message '" + m.name + "': no value for signal '" + s->name + "'");
    }
    if (auto r = encode(*s, it->second, f.data); !r) {
      return fail(ErrorCode::kInvalidArgument, "message '" + m.name + "', " + r.error().detail);
    }
    if (s->mux_role == MuxRole::kMultiplexor) selector = *get_raw(*s, f.data);
  }
  return f;
}

}  // namespace nav::protocols::dbc

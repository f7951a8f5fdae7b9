// twinlink_json: see twinlink_json.h. Portable C++11: the Arduino-ESP32 2.x core compiles
// sketches as gnu++11, the host tests as C++17.
#include "twinlink_json.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

namespace twinlink {

namespace {

bool is_digit(char c) { return c >= '0' && c <= '9'; }

bool fits(int written, size_t size) { return written >= 0 && static_cast<size_t>(written) < size; }

// The length of the valid UTF-8 sequence at s, 0 when there is none (RFC 3629: no overlong
// forms, no surrogates, nothing above U+10FFFF). Reads at most `available` bytes, and stops
// at the first byte that does not fit, so a NUL ends a cut-off sequence.
size_t utf8_length(const unsigned char* s, size_t available) {
  unsigned char c = s[0];
  if (c < 0x80) return 1;
  unsigned char low = 0x80, high = 0xBF;  // the range of the second byte
  size_t length;
  if (c >= 0xC2 && c <= 0xDF) {
    length = 2;
  } else if (c >= 0xE0 && c <= 0xEF) {
    length = 3;
    if (c == 0xE0) low = 0xA0;
    if (c == 0xED) high = 0x9F;
  } else if (c >= 0xF0 && c <= 0xF4) {
    length = 4;
    if (c == 0xF0) low = 0x90;
    if (c == 0xF4) high = 0x8F;
  } else {
    return 0;
  }
  if (available < 2 || s[1] < low || s[1] > high) return 0;
  for (size_t i = 2; i < length; ++i) {
    if (i >= available || s[i] < 0x80 || s[i] > 0xBF) return 0;
  }
  return length;
}

}  // namespace

// -- JsonWriter ------------------------------------------------------------------------------

JsonWriter::JsonWriter(char* out, size_t size)
    : out_(out), size_(size), length_(0), ok_(out != nullptr && size > 0) {
  if (ok_) out_[0] = '\0';
}

void JsonWriter::rewind(size_t length) {
  if (out_ == nullptr || size_ == 0 || length > length_) return;
  length_ = length;
  out_[length_] = '\0';
  ok_ = true;
}

void JsonWriter::put(const char* text, size_t length) {
  if (!ok_) return;
  if (length >= size_ - length_) {  // the NUL needs a byte too
    ok_ = false;
    return;
  }
  memcpy(out_ + length_, text, length);
  length_ += length;
  out_[length_] = '\0';
}

// A value or key that follows another in its object or array needs a comma. What was written
// last tells: nothing, an opening bracket or a key's colon need none.
void JsonWriter::separate() {
  if (!ok_ || length_ == 0) return;
  char last = out_[length_ - 1];
  if (last != '{' && last != '[' && last != ':') put(',');
}

JsonWriter& JsonWriter::open_object() {
  separate();
  put('{');
  return *this;
}

JsonWriter& JsonWriter::close_object() {
  put('}');
  return *this;
}

JsonWriter& JsonWriter::open_array() {
  separate();
  put('[');
  return *this;
}

JsonWriter& JsonWriter::close_array() {
  put(']');
  return *this;
}

JsonWriter& JsonWriter::key(const char* name) {
  separate();
  escaped(name);
  put(':');
  return *this;
}

JsonWriter& JsonWriter::number(double value) {
  if (!isfinite(value)) {  // JSON has no NaN or infinity, and the platform takes neither
    ok_ = false;
    return *this;
  }
  // 17 significant digits always read back as the same double; fewer are tried first so
  // 0.1 is sent as 0.1, not 0.10000000000000001. %g may write an exponent (1e-07), valid JSON.
  char text[32];
  int n = 0;
  for (int precision = 15; precision <= 17; ++precision) {
    n = snprintf(text, sizeof text, "%.*g", precision, value);
    if (!fits(n, sizeof text)) {
      ok_ = false;
      return *this;
    }
    if (strtod(text, nullptr) == value) break;
  }
  separate();
  put(text, static_cast<size_t>(n));
  return *this;
}

JsonWriter& JsonWriter::integer(uint64_t value) {
  char digits[24];  // 2^64 has 20 digits; no %llu, which not every embedded printf has
  size_t n = sizeof digits;
  do {
    digits[--n] = static_cast<char>('0' + value % 10);
    value /= 10;
  } while (value != 0);
  separate();
  put(digits + n, sizeof digits - n);
  return *this;
}

JsonWriter& JsonWriter::boolean(bool value) {
  separate();
  if (value) {
    put("true", 4);
  } else {
    put("false", 5);
  }
  return *this;
}

JsonWriter& JsonWriter::text(const char* value) {
  separate();
  escaped(value);
  return *this;
}

JsonWriter& JsonWriter::value(const Value& value) {
  switch (value.kind) {
    case Value::kNumber:
      return number(value.number);
    case Value::kBoolean:
      return boolean(value.boolean);
    case Value::kText:
      return text(value.text);
  }
  ok_ = false;  // a Kind that is none of the three
  return *this;
}

JsonWriter& JsonWriter::fields(const Field* fields, size_t count) {
  if (fields == nullptr && count > 0) ok_ = false;
  for (size_t i = 0; i < count && ok_; ++i) {
    key(fields[i].name).value(fields[i].value);
  }
  return *this;
}

// A JSON string: quotes and backslashes escaped, control characters as \n or \u00XX, other
// characters as they are. Text that is not UTF-8 is refused: the platform would refuse the
// whole message.
void JsonWriter::escaped(const char* text) {
  if (text == nullptr) {
    ok_ = false;
    return;
  }
  put('"');
  const unsigned char* s = reinterpret_cast<const unsigned char*>(text);
  while (*s != '\0' && ok_) {
    unsigned char c = *s;
    const char* escape = nullptr;
    switch (c) {
      case '"': escape = "\\\""; break;
      case '\\': escape = "\\\\"; break;
      case '\n': escape = "\\n"; break;
      case '\r': escape = "\\r"; break;
      case '\t': escape = "\\t"; break;
      case '\b': escape = "\\b"; break;
      case '\f': escape = "\\f"; break;
      default: break;
    }
    if (escape != nullptr) {
      put(escape, 2);
      ++s;
    } else if (c < 0x20) {
      char code[8];
      snprintf(code, sizeof code, "\\u%04x", c);
      put(code, 6);
      ++s;
    } else {
      size_t n = utf8_length(s, 4);  // NUL-terminated: the NUL stops a cut-off sequence
      if (n == 0) {
        ok_ = false;
        return;
      }
      put(reinterpret_cast<const char*>(s), n);
      s += n;
    }
  }
  put('"');
}

// -- JsonReader ------------------------------------------------------------------------------

namespace {

const char kTruncated[] = "the JSON ends too early";

int hex_digit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

}  // namespace

// Where a string being read goes; remembers when it did not fit.
struct JsonReader::Sink {
  char* out;
  size_t size;
  size_t length;
  bool overflow;

  void put(char c) {
    if (out == nullptr) return;
    if (length + 1 < size) {
      out[length++] = c;
    } else {
      overflow = true;
    }
  }
  void put_code_point(unsigned code) {
    if (code < 0x80) {
      put(static_cast<char>(code));
    } else if (code < 0x800) {
      put(static_cast<char>(0xC0 | (code >> 6)));
      put(static_cast<char>(0x80 | (code & 0x3F)));
    } else if (code < 0x10000) {
      put(static_cast<char>(0xE0 | (code >> 12)));
      put(static_cast<char>(0x80 | ((code >> 6) & 0x3F)));
      put(static_cast<char>(0x80 | (code & 0x3F)));
    } else {
      put(static_cast<char>(0xF0 | (code >> 18)));
      put(static_cast<char>(0x80 | ((code >> 12) & 0x3F)));
      put(static_cast<char>(0x80 | ((code >> 6) & 0x3F)));
      put(static_cast<char>(0x80 | (code & 0x3F)));
    }
  }
};

JsonReader::JsonReader(const char* text, size_t length)
    : p_(text), end_(text == nullptr ? text : text + length), error_(nullptr), depth_(0) {}

bool JsonReader::fail(const char* why) {
  if (error_ == nullptr) error_ = why;
  return false;
}

// Past whitespace; true when there is more.
bool JsonReader::more() {
  while (p_ < end_ && (*p_ == ' ' || *p_ == '\t' || *p_ == '\n' || *p_ == '\r')) ++p_;
  return p_ < end_;
}

bool JsonReader::take(char c) {
  if (!more() || *p_ != c) return false;
  ++p_;
  return true;
}

bool JsonReader::expect(char c, const char* why) {
  return take(c) || fail(more() ? why : kTruncated);
}

bool JsonReader::next_is_number() { return more() && (*p_ == '-' || is_digit(*p_)); }
bool JsonReader::next_is_object() { return more() && *p_ == '{'; }
bool JsonReader::at_end() { return !more(); }

bool JsonReader::hex4(unsigned* code) {
  if (end_ - p_ < 4) return fail(kTruncated);
  unsigned value = 0;
  for (int i = 0; i < 4; ++i) {
    int digit = hex_digit(*p_++);
    if (digit < 0) return fail("a \\u escape needs four hex digits");
    value = value * 16 + static_cast<unsigned>(digit);
  }
  *code = value;
  return true;
}

bool JsonReader::escape(Sink& sink) {
  if (p_ >= end_) return fail(kTruncated);
  char c = *p_++;
  switch (c) {
    case '"': case '\\': case '/': sink.put(c); return true;
    case 'b': sink.put('\b'); return true;
    case 'f': sink.put('\f'); return true;
    case 'n': sink.put('\n'); return true;
    case 'r': sink.put('\r'); return true;
    case 't': sink.put('\t'); return true;
    case 'u': break;
    default: return fail("an unknown escape in a string");
  }
  unsigned code;
  if (!hex4(&code)) return false;
  if (code >= 0xDC00 && code <= 0xDFFF) return fail("a lone surrogate in a string");
  if (code >= 0xD800 && code <= 0xDBFF) {  // the high half of a pair: the low half follows
    if (end_ - p_ < 2) return fail(kTruncated);
    if (p_[0] != '\\' || p_[1] != 'u') return fail("a lone surrogate in a string");
    p_ += 2;
    unsigned low;
    if (!hex4(&low)) return false;
    if (low < 0xDC00 || low > 0xDFFF) return fail("a lone surrogate in a string");
    code = 0x10000 + ((code - 0xD800) << 10) + (low - 0xDC00);
  }
  if (code == 0 && sink.out != nullptr) return fail("\\u0000 would cut the text short");
  sink.put_code_point(code);
  return true;
}

bool JsonReader::string(char* out, size_t size, bool* complete) {
  if (!more()) return fail(kTruncated);
  if (*p_ != '"') return fail("expected a string");
  ++p_;
  Sink sink = {size > 0 ? out : nullptr, size, 0, false};
  for (;;) {
    if (p_ >= end_) return fail(kTruncated);
    char c = *p_++;
    if (c == '"') break;
    if (static_cast<unsigned char>(c) < 0x20) return fail("a control character in a string");
    if (c == '\\') {
      if (!escape(sink)) return false;
    } else if (static_cast<unsigned char>(c) < 0x80) {
      sink.put(c);
    } else {  // a UTF-8 sequence, whole: the platform sends nothing else
      const unsigned char* start = reinterpret_cast<const unsigned char*>(p_ - 1);
      size_t n = utf8_length(start, static_cast<size_t>(end_ - (p_ - 1)));
      if (n == 0) return fail("a string that is not UTF-8");
      for (size_t i = 0; i < n; ++i) sink.put(static_cast<char>(start[i]));
      p_ += n - 1;
    }
  }
  if (sink.out != nullptr) out[sink.length] = '\0';
  if (complete != nullptr) *complete = !sink.overflow;
  return true;
}

bool JsonReader::digits() {
  if (p_ >= end_ || !is_digit(*p_)) return false;
  while (p_ < end_ && is_digit(*p_)) ++p_;
  return true;
}

// As JSON writes a number: -?(0|[1-9][0-9]*)(.[0-9]+)?([eE][+-]?[0-9]+)?
bool JsonReader::number(double* value) {
  if (!more()) return fail(kTruncated);
  const char* start = p_;
  if (*p_ == '-') ++p_;
  if (p_ < end_ && *p_ == '0') {
    ++p_;
  } else if (!digits()) {
    return fail(p_ >= end_ ? kTruncated : "expected a value");
  }
  if (p_ < end_ && *p_ == '.') {
    ++p_;
    if (!digits()) return fail("a number needs digits after its point");
  }
  if (p_ < end_ && (*p_ == 'e' || *p_ == 'E')) {
    ++p_;
    if (p_ < end_ && (*p_ == '+' || *p_ == '-')) ++p_;
    if (!digits()) return fail("a number needs digits in its exponent");
  }
  char text[64];  // strtod needs a NUL-terminated copy
  size_t n = static_cast<size_t>(p_ - start);
  if (n >= sizeof text) {  // only where it is not wanted: 63 characters hold any double
    return value == nullptr || fail("a number with too many digits");
  }
  memcpy(text, start, n);
  text[n] = '\0';
  double read = strtod(text, nullptr);
  if (!isfinite(read)) return fail("a number too large for a double");  // as the platform
  if (value != nullptr) *value = read;
  return true;
}

bool JsonReader::literal(const char* word) {
  size_t n = strlen(word);
  if (static_cast<size_t>(end_ - p_) < n) return fail(kTruncated);
  if (memcmp(p_, word, n) != 0) return fail("expected a value");
  p_ += n;
  return true;
}

bool JsonReader::scalar() {
  if (!more()) return fail(kTruncated);
  switch (*p_) {
    case '"': return string(nullptr, 0, nullptr);
    case 't': return literal("true");
    case 'f': return literal("false");
    case 'n': return literal("null");
    default: return number(nullptr);
  }
}

bool JsonReader::key() {
  return string(nullptr, 0, nullptr) && expect(':', "expected : after a key");
}

// A stack of the brackets still to close instead of recursion, so that hostile nesting
// cannot use up the (small: 8 KiB on an ESP32's loop task) stack.
bool JsonReader::skip() {
  char closers[kMaxDepth];
  int open = 0;
  for (;;) {
    if (!more()) return fail(kTruncated);
    char c = *p_;
    if (c == '{' || c == '[') {
      if (depth_ + open >= kMaxDepth) return fail("the JSON is nested too deeply");
      ++p_;
      closers[open++] = c == '{' ? '}' : ']';
      if (!take(closers[open - 1])) {  // not empty: its first element comes next
        if (c == '{' && !key()) return false;
        continue;
      }
      --open;
    } else if (!scalar()) {
      return false;
    }
    // A value ended: close what it ends, then a comma and the next element, or done.
    while (open > 0 && take(closers[open - 1])) --open;
    if (open == 0) return true;
    if (!expect(',', "expected , or a closing bracket")) return false;
    if (closers[open - 1] == '}' && !key()) return false;
  }
}

}  // namespace twinlink

// twinlink_json: just enough JSON for the messages of twinlink_mqtt.h, in portable C++11 with
// fixed buffers: no heap, no recursion, no Arduino headers.
#ifndef TWINLINK_JSON_H
#define TWINLINK_JSON_H

#include <stddef.h>
#include <stdint.h>

namespace twinlink {

static const int kMaxDepth = 32;      // deeper nesting is refused, not followed
static const size_t kMaxKey = 128;    // longer keys are read as "" (names have up to 128)

// One JSON value to send: a finite number, a bool or a UTF-8 text.
struct Value {
  enum Kind { kNumber, kBoolean, kText };
  Kind kind;
  double number;
  bool boolean;
  const char* text;

  static Value of_number(double value) { return Value{kNumber, value, false, nullptr}; }
  static Value of_bool(bool value) { return Value{kBoolean, 0.0, value, nullptr}; }
  static Value of_text(const char* value) { return Value{kText, 0.0, false, value}; }
};

// A named value: a signal in telemetry, a property, a field of a command's result.
struct Field {
  const char* name;
  Value value;
};

// Writes compact JSON into a fixed buffer, always NUL-terminated. Commas go in by themselves.
// A write that does not fit, or a value JSON cannot hold (NaN, infinity, text that is not
// UTF-8), makes ok() false until rewind(); later writes do nothing.
class JsonWriter {
 public:
  JsonWriter(char* out, size_t size);

  JsonWriter& open_object();
  JsonWriter& close_object();
  JsonWriter& open_array();
  JsonWriter& close_array();
  JsonWriter& key(const char* name);
  JsonWriter& number(double value);  // the shortest text that reads back as the same double
  JsonWriter& integer(uint64_t value);
  JsonWriter& boolean(bool value);
  JsonWriter& text(const char* value);
  JsonWriter& value(const Value& value);
  JsonWriter& fields(const Field* fields, size_t count);  // "name": value, ... (no braces)

  bool ok() const { return ok_; }
  size_t length() const { return length_; }
  const char* c_str() const { return out_; }
  // Back to an earlier length(), e.g. to undo a sample that did not fit; ok() again.
  void rewind(size_t length);

 private:
  void separate();
  void put(const char* text, size_t length);
  void put(char c) { put(&c, 1); }
  void escaped(const char* text);

  char* out_;
  size_t size_;
  size_t length_;
  bool ok_;
};

// Reads JSON (RFC 8259) from a buffer that need not be NUL-terminated, never past its end.
// Each read takes the value that comes next; on false, error() says why (the first reason).
class JsonReader {
 public:
  JsonReader(const char* text, size_t length);

  // A string into out (size bytes with the NUL; out nullptr: checked, not kept). *complete
  // (may be nullptr) says whether it fitted. \u0000 is refused: it would cut the text short.
  bool string(char* out, size_t size, bool* complete);
  bool number(double* value);  // value nullptr: checked, not kept
  bool skip();                 // any value, checked
  // An object: on_member(const char* key) -> bool is called for each member and must read or
  // skip its value.
  template <typename OnMember>
  bool object(OnMember on_member);

  bool next_is_number();
  bool next_is_object();
  bool at_end();  // nothing but whitespace is left
  bool fail(const char* why);  // refuse a well-formed value, with the reason
  const char* error() const { return error_; }

 private:
  struct Sink;
  bool more();
  bool take(char c);
  bool expect(char c, const char* why);
  bool hex4(unsigned* code);
  bool escape(Sink& sink);
  bool digits();
  bool literal(const char* word);
  bool scalar();
  bool key();

  const char* p_;
  const char* end_;
  const char* error_;
  int depth_;  // the objects being read by object()
};

template <typename OnMember>
bool JsonReader::object(OnMember on_member) {
  if (depth_ >= kMaxDepth) return fail("the JSON is nested too deeply");
  if (!expect('{', "expected an object")) return false;
  if (take('}')) return true;
  ++depth_;
  bool ok = true;
  for (;;) {
    char name[kMaxKey + 1];
    bool complete = false;
    ok = string(name, sizeof name, &complete) && expect(':', "expected : after a key") &&
         on_member(complete ? static_cast<const char*>(name) : "");
    if (!ok || take('}')) break;
    if (!expect(',', "expected , or } in an object")) {
      ok = false;
      break;
    }
  }
  --depth_;
  return ok;
}

}  // namespace twinlink

#endif  // TWINLINK_JSON_H

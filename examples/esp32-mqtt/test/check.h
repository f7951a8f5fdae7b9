// A test needs no framework: CHECK counts, reports where it failed and goes on.
#ifndef TWINLINK_TEST_CHECK_H
#define TWINLINK_TEST_CHECK_H

#include <stdio.h>
#include <string.h>

#include <memory>
#include <string>

namespace check {

inline int& failures() {
  static int count = 0;
  return count;
}

inline int& checks() {
  static int count = 0;
  return count;
}

inline void report(bool ok, const char* file, int line, const char* what) {
  ++checks();
  if (ok) return;
  ++failures();
  fprintf(stderr, "%s:%d: failed: %s\n", file, line, what);
}

inline void report_text(const char* got, const char* want, const char* file, int line) {
  bool ok = got != nullptr && want != nullptr && strcmp(got, want) == 0;
  ++checks();
  if (ok) return;
  ++failures();
  fprintf(stderr, "%s:%d: failed:\n  got:  %s\n  want: %s\n", file, line,
          got ? got : "(null)", want ? want : "(null)");
}

// A copy of text in a heap block of exactly its length, no NUL after it: a read past the end
// is an AddressSanitizer error, as a read past PubSubClient's payload would be on the board.
struct Exact {
  std::unique_ptr<char[]> bytes;
  size_t length;

  explicit Exact(const std::string& text) : bytes(new char[text.size()]), length(text.size()) {
    if (length > 0) memcpy(bytes.get(), text.data(), length);
  }
  const char* data() const { return bytes.get(); }
};

}  // namespace check

#define CHECK(condition) check::report((condition), __FILE__, __LINE__, #condition)
#define CHECK_TEXT(got, want) check::report_text((got), (want), __FILE__, __LINE__)

#endif  // TWINLINK_TEST_CHECK_H

// What the fuzz targets hold every input to: a finding aborts with its reason (libFuzzer keeps
// the input), and a refusal's message keeps the error contract of lib/task_io.h.
#ifndef LINKFIT_TESTS_FUZZ_FUZZ_CONTRACT_H_
#define LINKFIT_TESTS_FUZZ_FUZZ_CONTRACT_H_

#include <cstdio>
#include <cstdlib>
#include <string>

namespace linkfit::fuzz {

// Prints "<target>: <what>" and aborts.
[[noreturn]] inline void Finding(const char* target, const std::string& what) {
  std::fprintf(stderr, "%s: %s\n", target, what.c_str());
  std::abort();
}

// "<source>: ..." on one printable line, or a finding.
inline void CheckMessage(const char* target, const char* source, const char* what) {
  const std::string message = what;
  if (message.rfind(std::string(source) + ": ", 0) != 0) {
    Finding(target, "message does not start with the source: " + message);
  }
  for (const char c : message) {
    if (c < 0x20 || c >= 0x7f) Finding(target, "unprintable byte in message: " + message);
  }
}

}  // namespace linkfit::fuzz

#endif  // LINKFIT_TESTS_FUZZ_FUZZ_CONTRACT_H_

// libFuzzer target for the whole solve: any text that ParseTask accepts (at most kMaxItems poses,
// points or pairs, so that an input runs in milliseconds) is solved at its own effort level, as
// `linkfit solve` would, and its result written as JSON. A task the solver refuses ends in an
// InputError with one printable line naming the source. Anything else (another exception, a
// crash, a dependency's assertion such as Ceres' CHECK, a sanitizer report, a non-finite number
// or an unparsable result) is a finding. Built with -fsanitize=fuzzer by scripts/fuzz.sh;
// replay_main.cc runs it on the corpus in every build (FuzzSolveCorpusReplay).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <nlohmann/json.hpp>
#include <string>

#include "lib/result_io.h"
#include "lib/task_io.h"
#include "optimizers/task_solver.h"
#include "tests/fuzz/fuzz_contract.h"

namespace {

constexpr char kSource[] = "fuzz.json";
constexpr size_t kMaxItems = 16;

[[noreturn]] void Finding(const std::string& what) { linkfit::fuzz::Finding("fuzz_solve", what); }

void CheckMessage(const char* what) { linkfit::fuzz::CheckMessage("fuzz_solve", kSource, what); }

// Every number of the result finite (the writer has no NaN or infinity to give: a missing
// value is left out or null with its note).
void CheckNumbers(const nlohmann::json& value, const std::string& where) {
  if (value.is_number_float()) {
    const double number = value.get<double>();
    if (!std::isfinite(number)) Finding("non-finite number at " + where);
  } else if (value.is_object()) {
    for (const auto& [key, item] : value.items()) CheckNumbers(item, where + "." + key);
  } else if (value.is_array()) {
    for (size_t k = 0; k < value.size(); ++k) {
      CheckNumbers(value[k], where + "[" + std::to_string(k) + "]");
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  linkfit::TaskReadOptions small;
  small.max_items = kMaxItems;
  linkfit::Task task;
  try {
    task = linkfit::ParseTask(text, kSource, small);
  } catch (const linkfit::InputError& error) {
    CheckMessage(error.what());
    return 0;
  }
  std::string json;
  try {
    json = linkfit::ResultToJson(linkfit::SolveTask(task), 2);
  } catch (const linkfit::InputError& error) {
    CheckMessage(error.what());
    return 0;
  } catch (const std::exception& error) {
    Finding(std::string("solve threw: ") + error.what());
  }
  nlohmann::json result;
  try {
    result = nlohmann::json::parse(json);
  } catch (const std::exception& error) {
    Finding(std::string("unparsable result: ") + error.what());
  }
  CheckNumbers(result, "result");
  return 0;
}

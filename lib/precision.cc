#include "lib/precision.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>

namespace linkfit {
namespace {

constexpr double kEpsilon = std::numeric_limits<double>::epsilon();
// Exponents beyond this are clamped: 10^-400 is 0 and 10^400 infinite in double anyway.
constexpr long kExponentClamp = 400;

double HalfUnitAt(int exponent) { return 0.5 * std::pow(10.0, exponent); }

}  // namespace

bool ReadWrittenDigits(const std::string& text, WrittenDigits* digits) {
  size_t i = 0;
  if (i < text.size() && (text[i] == '-' || text[i] == '+')) ++i;
  long integer_digits = 0, fraction_digits = 0, first_nonzero = -1, position = 0;
  const auto digit = [&](char c) {
    if (c != '0' && first_nonzero < 0) first_nonzero = position;
    ++position;
  };
  for (; i < text.size() && std::isdigit(static_cast<unsigned char>(text[i])); ++i) {
    digit(text[i]);
    ++integer_digits;
  }
  if (i < text.size() && text[i] == '.') {
    for (++i; i < text.size() && std::isdigit(static_cast<unsigned char>(text[i])); ++i) {
      digit(text[i]);
      ++fraction_digits;
    }
  }
  if (integer_digits + fraction_digits == 0) return false;
  long exponent = 0;
  if (i < text.size() && (text[i] == 'e' || text[i] == 'E')) {
    ++i;
    bool negative = false;
    if (i < text.size() && (text[i] == '-' || text[i] == '+')) negative = text[i++] == '-';
    if (i >= text.size() || !std::isdigit(static_cast<unsigned char>(text[i]))) return false;
    for (; i < text.size() && std::isdigit(static_cast<unsigned char>(text[i])); ++i) {
      exponent = std::min(exponent * 10 + (text[i] - '0'), kExponentClamp * 10);
    }
    if (negative) exponent = -exponent;
  }
  if (i != text.size()) return false;
  const auto clamp = [](long value) {
    return static_cast<int>(std::clamp(value, -kExponentClamp, kExponentClamp));
  };
  digits->last = clamp(exponent - fraction_digits);
  digits->zero = first_nonzero < 0;
  digits->lead = digits->zero ? digits->last : clamp(integer_digits - 1 - first_nonzero + exponent);
  return true;
}

void DigitTally::Add(const WrittenDigits& digits) {
  ++count_;
  for (Pattern& pattern : patterns_) {
    if (pattern.last == digits.last && pattern.lead == digits.lead && pattern.zero == digits.zero) {
      ++pattern.count;
      return;
    }
  }
  patterns_.push_back({digits.last, digits.lead, digits.zero, 1});
}

bool DigitTally::SignificantDigits() const {
  int significant = 0, finest = std::numeric_limits<int>::max();
  long nonzero = 0;
  for (const Pattern& pattern : patterns_) {
    if (pattern.zero) continue;
    significant = std::max(significant, pattern.lead - pattern.last + 1);
    finest = std::min(finest, pattern.last);
    nonzero += pattern.count;
  }
  // Numbers that show all S digits: in a fixed-decimal table they are the largest decade's
  // (one leading exponent); in a significant-digit table most numbers, of every magnitude.
  long full = 0;
  int lowest_lead = std::numeric_limits<int>::max(), highest_lead = std::numeric_limits<int>::min();
  // Trailing zeros each reading says were dropped: printed to the finest decimal, a number
  // dropped (last - finest); printed to S digits, (S - its digits). Each dropped zero is a 1 in
  // 10 event for measured values.
  long dropped_fixed = 0, dropped_significant = 0;
  for (const Pattern& pattern : patterns_) {
    if (pattern.zero) continue;
    const int digits = pattern.lead - pattern.last + 1;
    dropped_fixed += pattern.count * (pattern.last - finest);
    dropped_significant += pattern.count * (significant - digits);
    if (digits != significant) continue;
    full += pattern.count;
    lowest_lead = std::min(lowest_lead, pattern.lead);
    highest_lead = std::max(highest_lead, pattern.lead);
  }
  // Evidently significant digits: the full numbers span decades, and they are most of the table
  // or the fixed reading needs at least twice the dropped zeros.
  return full > 0 && highest_lead > lowest_lead &&
         (4 * full >= 3 * nonzero || 2 * dropped_significant <= dropped_fixed);
}

double DigitTally::HalfUnit() const {
  if (patterns_.empty()) return 0.0;
  // The table's significant digits S (the most any number shows) and its finest last digit.
  // The finest decimal of the numbers that are not zero (a zero printed "0.00000" by a table of
  // six significant digits shows more decimals than any of its numbers); of the zeros when every
  // number is one.
  int significant = 1, finest = std::numeric_limits<int>::max(), finest_zero = finest;
  for (const Pattern& pattern : patterns_) {
    if (pattern.zero) {
      finest_zero = std::min(finest_zero, pattern.last);
      continue;
    }
    significant = std::max(significant, pattern.lead - pattern.last + 1);
    finest = std::min(finest, pattern.last);
  }
  if (finest == std::numeric_limits<int>::max()) finest = finest_zero;
  const double floor = HalfUnitAt(finest);
  if (!SignificantDigits()) return floor;
  double coarsest = floor;
  for (const Pattern& pattern : patterns_) {
    if (pattern.zero) continue;
    // As written, or as the table's S digits give it when trailing zeros were dropped.
    const double half_unit =
        std::min(HalfUnitAt(pattern.last), HalfUnitAt(pattern.lead - significant + 1));
    coarsest = std::max(coarsest, half_unit);
  }
  return coarsest;
}

double RelativePrecision(const DataPrecision& precision, double length) {
  double relative = precision.angle;
  if (length > 0.0) relative = std::max(relative, precision.length / length);
  return std::max(relative, 2.0 * kEpsilon);
}

double PointUncertainty(const DataPrecision& precision, double distance, double scale,
                        int dimension) {
  return std::max(
      std::sqrt(static_cast<double>(dimension)) * precision.length + distance * precision.angle,
      4.0 * kEpsilon * scale);
}

std::string PrecisionText(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.2g", value);
  return buffer;
}

}  // namespace linkfit

// The precision a task's data carry (README, "Data from tables and measurements").
//
// Data come from tables, CAD exports and measurements printed to a few digits. Every task has
// a precision: given in the task ("precision": {"length": delta, "angle_deg": alpha}) or
// inferred from the numbers as written. A number written with its last digit in the decimal
// place 10^k is known to half a unit there, 0.5 * 10^k ("12.3456": 5e-5). The precision of a
// kind of number (lengths; angles, and dimensionless entries such as quaternion or rotation
// components) is read one of two ways (issue 34):
//   fixed decimals (the default): the table is printed to the finest decimal place of its
//     numbers that are not zero, and every number is known to half a unit there ("0.05", "0.15",
//     "1.1" and "12.35": 0.005; "1.1" is "1.10" with its trailing zero dropped);
//   significant digits: a table evidently printed to S significant digits (mixed magnitudes:
//     the numbers that show the most digits, S, span more than one decade, and they are three
//     quarters of the numbers or the fixed reading needs twice the dropped trailing zeros) gives
//     each number 0.5 * 10^(e - S + 1) (e its leading decimal exponent), so the largest number of
//     the kind decides (its digits are the coarsest), and a number whose trailing zeros were
//     dropped ("1.5" in a table of six digits) counts with the table's S.
// Full-precision doubles get rounding level.
//
// The solvers use the precision to choose models (slider or circle, plane or sphere, planar or
// spatial, a family of solutions or isolated ones), to repair input within it and refuse input
// beyond it, and to bound the error of their answers.
#ifndef LINKFIT_LIB_PRECISION_H_
#define LINKFIT_LIB_PRECISION_H_

#include <string>
#include <vector>

namespace linkfit {

struct DataPrecision {
  double length = 0.0;  // length units; 0: rounding level
  double angle = 0.0;   // radians; 0: rounding level
  // "task" when the task gives "precision", "digits" when inferred from the numbers as written
  // (tasks built in code, with no text, count as full-precision digits).
  std::string source = "digits";
};

// How a JSON number was written: the decimal exponent of its last written digit and of its
// leading non-zero digit ("0.01230": last -5, lead -2; "1200": last 0, lead 3).
struct WrittenDigits {
  int last = 0;
  int lead = 0;
  bool zero = false;  // every digit is zero: no leading digit
};

// Reads a JSON number token ("-12.50e-3"). Returns false when `text` is not one.
bool ReadWrittenDigits(const std::string& text, WrittenDigits* digits);

// The digits of the numbers of one kind in a task, and the precision they imply (file comment).
class DigitTally {
 public:
  void Add(const WrittenDigits& digits);
  bool empty() const { return count_ == 0; }
  // Half a unit of the last written digit: of the finest over the kind (fixed decimals), or of
  // the coarsest after the table's significant digits are taken into account (a table printed
  // to significant digits; file comment); 0 when empty.
  double HalfUnit() const;
  // Whether the numbers read as a table printed to significant digits (file comment).
  bool SignificantDigits() const;

 private:
  // Distinct (last, lead) pairs with the zero flag: tables repeat a few patterns, so this stays
  // small whatever the number of poses.
  struct Pattern {
    int last;
    int lead;
    bool zero;
    long count;
  };
  std::vector<Pattern> patterns_;
  long count_ = 0;
};

// Relative precision of data of characteristic length `length`: the larger of delta / L and
// alpha (radians), never below double rounding.
double RelativePrecision(const DataPrecision& precision, double length);

// How far a point of the moving body, `distance` from its frame's origin, can be from where
// the data put it: sqrt(dimension) delta (the origin's coordinates) + distance * alpha. Never
// below rounding of `scale` (the size of the numbers involved).
double PointUncertainty(const DataPrecision& precision, double distance, double scale,
                        int dimension = 2);

// "5e-05" style text of a precision figure for messages and notes.
std::string PrecisionText(double value);

}  // namespace linkfit

#endif  // LINKFIT_LIB_PRECISION_H_

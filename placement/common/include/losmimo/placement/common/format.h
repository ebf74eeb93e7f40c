#pragma once
// Numbers as text: the one home of every number format losmimo writes.
//   format_double(v)           shortest text that reads back to exactly v ("0.3", not
//                              "0.29999999999999999"): INI values
//   format_g(v, digits)        printf "%.<digits>g"; non-finite values as "nan", "inf", "-inf"
//                              (the sign of a NaN is dropped): CSV columns use kCsvDigits,
//                              records that must read back exactly use kExactDigits
//   format_exact(v)            format_g(v, kExactDigits): records and INI values that read back exactly
//   format_csv(v)              format_g(v, kCsvDigits): CSV columns
//   format_fixed(v, decimals)  printf "%.<decimals>f", or "n/a" for a non-finite value: reports
//   format_hex64(v)            16 lower-case hex digits: digests

#include <cstdint>
#include <string>

namespace losmimo::common {

inline constexpr int kCsvDigits = 10;
inline constexpr int kExactDigits = 17;

std::string format_double(double value);
std::string format_g(double value, int digits);
inline std::string format_exact(double value) { return format_g(value, kExactDigits); }
inline std::string format_csv(double value) { return format_g(value, kCsvDigits); }
std::string format_fixed(double value, int decimals);
std::string format_hex64(std::uint64_t value);

}  // namespace losmimo::common

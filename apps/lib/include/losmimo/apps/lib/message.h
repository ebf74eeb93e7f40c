#pragma once
// A message as a terminal shows it. Messages quote the offending value ('...'); a value can be
// megabytes long or hold bytes a terminal does not show (a UTF-8 byte-order mark, control
// characters). printable_message escapes every byte that is not printable ASCII or part of a
// valid UTF-8 character as \xHH (a BOM is always escaped: it is invisible), and shortens each quoted
// value longer than kMaxQuotedBytes to its start, "...", and its length, so the message
// keeps what surrounds the value (file, line, field, and why it is wrong).

#include <cstddef>
#include <string>
#include <string_view>

namespace losmimo::apps {

inline constexpr std::size_t kMaxQuotedBytes = 256;

std::string printable_message(std::string_view message);

}  // namespace losmimo::apps

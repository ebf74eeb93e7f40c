#include "losmimo/apps/lib/message.h"

#include <cstdio>

namespace losmimo::apps {

namespace {

// Length of the valid UTF-8 character (2..4 bytes, no overlong form, no surrogate) at text[i],
// or 0.
std::size_t utf8_length(std::string_view text, std::size_t i) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned char c = byte(i);
  std::size_t n = 0;
  unsigned min = 0;
  unsigned code = 0;
  if (c >= 0xC2 && c <= 0xDF) {
    n = 2, code = c & 0x1F, min = 0x80;
  } else if (c >= 0xE0 && c <= 0xEF) {
    n = 3, code = c & 0x0F, min = 0x800;
  } else if (c >= 0xF0 && c <= 0xF4) {
    n = 4, code = c & 0x07, min = 0x10000;
  } else {
    return 0;
  }
  if (i + n > text.size()) return 0;
  for (std::size_t k = 1; k < n; ++k) {
    if ((byte(i + k) & 0xC0) != 0x80) return 0;
    code = (code << 6) | (byte(i + k) & 0x3F);
  }
  if (code < min || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF) || code == 0xFEFF) return 0;
  return n;
}

// Escapes what a terminal would not show; keeps '\n' (messages may span lines) and '\t'.
std::string escaped(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size();) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if ((c >= 0x20 && c < 0x7F) || c == '\n' || c == '\t') {
      out += static_cast<char>(c);
      ++i;
      continue;
    }
    if (const std::size_t n = utf8_length(text, i); n > 0) {
      out.append(text.substr(i, n));
      i += n;
      continue;
    }
    char hex[8];
    std::snprintf(hex, sizeof hex, "\\x%02X", c);
    out += hex;
    ++i;
  }
  return out;
}

// A quoted value: its start (never cutting a UTF-8 character), "...", and its size.
std::string shortened(std::string_view value) {
  if (value.size() <= kMaxQuotedBytes) return escaped(value);
  std::size_t keep = kMaxQuotedBytes / 2;
  while (keep > 0 && (static_cast<unsigned char>(value[keep]) & 0xC0) == 0x80) --keep;
  return escaped(value.substr(0, keep)) + "... (" + std::to_string(value.size()) + " bytes)";
}

}  // namespace

std::string printable_message(std::string_view message) {
  std::string out;
  std::size_t i = 0;
  while (i < message.size()) {
    const std::size_t open = message.find('\'', i);
    if (open == std::string_view::npos) break;
    const std::size_t close = message.find('\'', open + 1);
    if (close == std::string_view::npos) break;
    out += escaped(message.substr(i, open + 1 - i));
    out += shortened(message.substr(open + 1, close - open - 1));
    out += '\'';
    i = close + 1;
  }
  // The rest (no more quoted values); a long unquoted tail (a whole line echoed) is shortened too.
  const std::string_view tail = message.substr(i);
  out += tail.size() > 16 * kMaxQuotedBytes ? shortened(tail) : escaped(tail);
  return out;
}

}  // namespace losmimo::apps

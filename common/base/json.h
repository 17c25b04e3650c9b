// JSON text for the programs' hand-written --json output (which is not a protobuf message;
// messages go through google::protobuf::util::MessageToJsonString).
#pragma once

#include <string>
#include <string_view>

namespace igms {

// `text` as the inside of a JSON string: quote, backslash and control characters escaped
// (\n and \t by name, the others as \u00XX); other bytes, UTF-8 included, pass unchanged.
std::string JsonEscape(std::string_view text);

// `text` as a JSON string, quotes included.
inline std::string JsonQuote(std::string_view text) { return '"' + JsonEscape(text) + '"'; }

}  // namespace igms

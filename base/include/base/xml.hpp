// Text for XML and SVG: the one escape every picture writer uses (sched's loop pictures, paper's charts).
#pragma once

#include <string>

namespace nesshi::base {

// s with &, <, > and " escaped, for element text and attribute values.
inline std::string xml_escape(const std::string& s) {
    std::string o;
    for (char c : s) {
        if (c == '&') o += "&amp;";
        else if (c == '<') o += "&lt;";
        else if (c == '>') o += "&gt;";
        else if (c == '"') o += "&quot;";
        else o += c;
    }
    return o;
}

} // namespace nesshi::base

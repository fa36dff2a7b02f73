#include "core/modes.hpp"

#include <cmath>
#include <sstream>

#include "core/errors.hpp"

namespace cs {

const char* to_string(Strategy s) { return s == Strategy::columns ? "columns" : "tree"; }

Strategy parse_strategy(const std::string& text) {
    if (text == "tree") return Strategy::tree;
    if (text == "columns") return Strategy::columns;
    throw ParameterError("strategy must be 'tree' or 'columns', not '" + text + "'");
}

const char* to_string(OrientMode m) {
    switch (m) {
        case OrientMode::automatic: return "auto";
        case OrientMode::keep: return "keep";
        case OrientMode::euler: return "euler";
    }
    return "auto";
}

OrientRequest parse_orient(const std::string& text) {
    OrientRequest r;
    if (text == "auto") return r;
    if (text == "keep") {
        r.mode = OrientMode::keep;
        return r;
    }
    std::istringstream in(text);
    auto& a = r.degrees;
    char c1 = 0, c2 = 0;
    if (!(in >> a[0] >> c1 >> a[1] >> c2 >> a[2]) || c1 != ',' || c2 != ',' || !in.eof() || !std::isfinite(a[0]) ||
        !std::isfinite(a[1]) || !std::isfinite(a[2]))
        throw ParameterError("--orient must be auto, keep or RX,RY,RZ in degrees (e.g. 90,0,0), not '" + text + "'");
    r.mode = OrientMode::euler;
    return r;
}

}  // namespace cs

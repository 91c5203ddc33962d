// The tuning controls' values as text (sample.hpp: parse_control_value, control_value_text).
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "fx/error.hpp"
#include "sample.hpp"
#include "cellfx_names.hpp"

namespace cellfx_samples {

namespace {

std::string number_text(double v) {
    char b[40];
    std::snprintf(b, sizeof b, "%.17g", v); // exact: a saved value reads back the same
    return b;
}

double parse_number(const Control& c, const std::string& text) {
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || errno == ERANGE || !std::isfinite(v))
        throw fx::Error(c.name + ": expected a number, got '" + text + "'");
    return v;
}

} // namespace

Control parse_control_value(const Control& control, const std::string& text) {
    Control c = control;
    switch (c.kind) {
    case Control::Kind::Toggle:
        if (text == "true" || text == "on" || text == "1") c.toggle = true;
        else if (text == "false" || text == "off" || text == "0") c.toggle = false;
        else throw fx::Error(c.name + ": expected true or false, got '" + text + "'");
        break;
    case Control::Kind::Choice: {
        std::string names;
        for (const std::string& choice : c.choices) {
            if (choice == text) {
                c.choice = text;
                return c;
            }
            names += (names.empty() ? "" : ", ") + choice;
        }
        throw fx::Error(c.name + ": expected one of " + names + ", got '" + text + "'");
    }
    case Control::Kind::Number:
    case Control::Kind::Integer: {
        const double v = parse_number(c, text);
        const bool integer = c.kind == Control::Kind::Integer;
        if ((integer && v != std::floor(v)) || !c.range.contains(v))
            throw fx::Error(c.name + " " + c.range.requirement(integer) + ", got " + text);
        c.number = v;
        break;
    }
    case Control::Kind::Vector:
    case Control::Kind::Direction: {
        std::stringstream in(text);
        std::string item;
        int k = 0;
        for (; k < 3 && std::getline(in, item, ','); ++k) c.vector[k] = parse_number(c, item);
        if (k != 3 || std::getline(in, item, ','))
            throw fx::Error(c.name + ": expected three numbers x,y,z, got '" + text + "'");
        for (int i = 0; i < 3; ++i)
            if (!c.range.contains(c.vector[i])) throw fx::Error(c.name + ": each component " + c.range.requirement(false) + ", got " + text);
        if (c.kind == Control::Kind::Direction && c.vector == glm::dvec3(0.0)) throw fx::Error(c.name + ": must not be zero");
        break;
    }
    }
    return c;
}

std::string control_value_text(const Control& c) {
    switch (c.kind) {
    case Control::Kind::Toggle: return c.toggle ? "true" : "false";
    case Control::Kind::Choice: return c.choice;
    case Control::Kind::Number:
    case Control::Kind::Integer: return number_text(c.number);
    case Control::Kind::Vector:
    case Control::Kind::Direction:
        return number_text(c.vector.x) + "," + number_text(c.vector.y) + "," + number_text(c.vector.z);
    }
    return "";
}

void SampleContent::set_control(const std::string& group, const Control& value) {
    throw fx::Error("no control '" + group + "." + value.name + "' in this sample");
}

} // namespace cellfx_samples

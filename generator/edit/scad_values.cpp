#include "edit/scad_values.hpp"

#include <cctype>
#include <cstdio>
#include <cstdlib>

#include "core/errors.hpp"

namespace cs {
namespace {

class Parser {
public:
    Parser(const std::string& text, const std::string& file) : s_(text), file_(file) {}

    ScadValues all() {
        ScadValues out;
        for (skip_space(); pos_ < s_.size(); skip_space()) {
            size_t start = pos_;
            int line = line_;
            std::string name = identifier();
            skip_space();
            if (name.empty() || !eat('=')) {  // not an assignment: the code after the data
                pos_ = start;
                break;
            }
            ScadValue v;
            v.line = line;
            skip_space();
            v.begin = pos_;
            bool plain = value(v.value, &v.item_lines);
            v.end = pos_;
            skip_space();
            if (!eat(';')) fail("expected ';' after the value of " + name);
            if (!plain) continue;  // refers to other names: not data
            if (out.count(name)) fail(name + " is assigned twice (first on line " + std::to_string(out[name].line) + ")", line);
            out[name] = std::move(v);
        }
        return out;
    }

private:
    [[noreturn]] void fail(const std::string& what, int line = -1) const {
        throw InputError(file_ + ":" + std::to_string(line < 0 ? line_ : line) + ": " + what);
    }

    bool eat(char c) {
        if (pos_ < s_.size() && s_[pos_] == c) {
            ++pos_;
            return true;
        }
        return false;
    }

    void skip_space() {
        while (pos_ < s_.size()) {
            char c = s_[pos_];
            if (c == '\n') ++line_, ++pos_;
            else if (std::isspace(static_cast<unsigned char>(c))) ++pos_;
            else if (s_.compare(pos_, 2, "//") == 0) {
                while (pos_ < s_.size() && s_[pos_] != '\n') ++pos_;
            } else if (s_.compare(pos_, 2, "/*") == 0) {
                int line = line_;
                size_t end = s_.find("*/", pos_ + 2);
                if (end == std::string::npos) fail("a comment /* is never closed", line);
                for (size_t i = pos_; i < end; ++i) line_ += s_[i] == '\n';
                pos_ = end + 2;
            } else {
                break;
            }
        }
    }

    std::string identifier() {
        size_t start = pos_;
        if (pos_ < s_.size() && (std::isalpha(static_cast<unsigned char>(s_[pos_])) || s_[pos_] == '_' || s_[pos_] == '$'))
            while (pos_ < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[pos_])) || s_[pos_] == '_' || s_[pos_] == '$'))
                ++pos_;
        return s_.substr(start, pos_ - start);
    }

    // Parses one value into `out`; false (after consuming it) when it refers to other names.
    bool value(nlohmann::json& out, std::vector<int>* item_lines = nullptr) {
        if (pos_ >= s_.size()) fail("the file ends where a value belongs");
        char c = s_[pos_];
        if (c == '[') return list(out, item_lines);
        if (c == '"') return string(out);
        if (c == '-' || c == '+' || c == '.' || std::isdigit(static_cast<unsigned char>(c))) return number(out);
        std::string word = identifier();
        if (word.empty()) fail(std::string("unexpected '") + c + "' where a value belongs");
        skip_space();
        if (pos_ < s_.size() && s_[pos_] != ',' && s_[pos_] != ']' && s_[pos_] != ';')
            fail("expected a plain value (a number, true/false, a string or a list), found an expression after '" + word + "'");
        if (word == "true" || word == "false") out = word == "true";
        else if (word == "undef") out = nullptr;
        else return false;
        return true;
    }

    bool number(nlohmann::json& out) {
        const char* begin = s_.c_str() + pos_;
        char* end = nullptr;
        double v = std::strtod(begin, &end);
        if (end == begin) fail("malformed number");
        pos_ += static_cast<size_t>(end - begin);
        skip_space();
        if (pos_ < s_.size() && s_[pos_] != ',' && s_[pos_] != ']' && s_[pos_] != ';')
            fail(std::string("expected a plain value (a number, true/false, a string or a list), found '") + s_[pos_] +
                 "' after a number");
        out = v;
        return true;
    }

    bool string(nlohmann::json& out) {
        int line = line_;
        std::string text;
        for (++pos_; pos_ < s_.size() && s_[pos_] != '"'; ++pos_) {
            if (s_[pos_] == '\n') fail("a string is not closed on its line", line);
            if (s_[pos_] == '\\' && pos_ + 1 < s_.size()) ++pos_;
            text += s_[pos_];
        }
        if (!eat('"')) fail("a string is never closed", line);
        out = text;
        return true;
    }

    bool list(nlohmann::json& out, std::vector<int>* item_lines) {
        int line = line_;
        ++pos_;  // '['
        out = nlohmann::json::array();
        bool plain = true;
        for (skip_space(); !eat(']'); skip_space()) {
            if (pos_ >= s_.size()) fail("a list opened here is never closed with ']'", line);
            if (item_lines) item_lines->push_back(line_);
            nlohmann::json item;
            plain = value(item) && plain;
            out.push_back(std::move(item));
            skip_space();
            if (eat(']')) break;
            if (!eat(',')) {
                if (pos_ >= s_.size()) fail("a list opened here is never closed with ']'", line);
                fail(std::string("malformed list: expected ',' or ']', found '") + s_[pos_] + "'");
            }
        }
        return plain;
    }

    const std::string& s_;
    const std::string& file_;
    size_t pos_ = 0;
    int line_ = 1;
};

}  // namespace

ScadValues parse_scad_values(const std::string& text, const std::string& file) { return Parser(text, file).all(); }

std::string scad_literal(const nlohmann::json& value) {
    if (value.is_null()) return "undef";
    if (value.is_boolean()) return value.get<bool>() ? "true" : "false";
    if (value.is_number()) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%.10g", value.get<double>());
        return buf;
    }
    if (value.is_string()) return value.dump();  // JSON's escapes are OpenSCAD's: \" \\ \n \t
    std::string s = "[";
    for (size_t i = 0; i < value.size(); ++i) s += (i ? ", " : "") + scad_literal(value[i]);
    return s + "]";
}

std::string with_scad_value(const std::string& text, const std::string& name, const nlohmann::json& value,
                            const std::string& file) {
    ScadValues values = parse_scad_values(text, file);
    auto it = values.find(name);
    if (it == values.end())
        throw InputError(file + ": " + name + " is missing; it is not a .scad file clever-support wrote, or the line "
                         "assigning " + name + " was removed");
    const ScadValue& v = it->second;
    return text.substr(0, v.begin) + scad_literal(value) + text.substr(v.end);
}

}  // namespace cs

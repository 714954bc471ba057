// Custom G-code expansion: a small recursive-descent evaluator for the subset of PrusaSlicer's
// macro language that printer profiles use (numbers, strings, vector indices, + - * /, min/max,
// comparisons, regex match, and/or/not, if/elsif/else/endif). Anything beyond it is reported,
// never guessed: the affected line becomes a comment.
//
// Hostile profiles are bounded: expressions nest at most kMaxDepth deep (parentheses, unary
// operators, calls: each one a level of recursion), a tag holds at most kMaxTag characters,
// a string value at most kMaxString, the custom G-code at most kMaxText; regular expressions
// are matched in linear time (base/linear_regex.hpp), never by backtracking std::regex.
#include "gcode/placeholders.hpp"

#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "base/error.hpp"
#include "base/linear_regex.hpp"
#include "base/numbers.hpp"
#include "config/setting_table.hpp"
#include "gcode/safe_text.hpp"

namespace carve {

namespace {

constexpr int kMaxDepth = 100;
constexpr size_t kMaxTag = 1 << 16;
constexpr size_t kMaxString = 1 << 20;
constexpr size_t kMaxText = 4 << 20;

// A placeholder may stand for a profile value of up to the profile's 16 MB, and the text may hold
// a million of them: the expansion is bounded as it grows, not only the text going in.
void check_expanded_size(const std::string& out) {
    if (out.size() > kMaxText)
        throw InputError(
            "the profile's custom G-code expands to more than 4 MB (a placeholder stands for a "
            "very long value?); shorten it");
}

struct Value {
    bool is_number = true;
    double number = 0;
    std::string text;

    std::string str() const {
        if (!is_number) return text;
        if (number == std::floor(number) && std::abs(number) < 1e15)
            return fmt::format("{}", static_cast<long long>(number));
        return fmt::format("{}", number);
    }
    bool truthy() const { return is_number ? number != 0 : !text.empty(); }
};

Value num(double d) {
    return {true, d, {}};
}
Value text(std::string s) {
    return {false, 0, std::move(s)};
}

struct Unresolved : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// A tag as quoted in a note: hostile ones are kilobytes long.
std::string shorten(const std::string& tag) {
    return tag.size() > 80 ? tag.substr(0, 77) + "..." : tag;
}

std::string trim(const std::string& s) {
    const size_t a = s.find_first_not_of(" \t");
    if (a == std::string::npos) return {};
    return s.substr(a, s.find_last_not_of(" \t") - a + 1);
}

// One element of a profile value: "1500,1250" holds two numbers, "\"a\";\"b\"" two strings.
std::optional<Value> profile_element(const std::string& raw, size_t index) {
    std::vector<std::string> items;
    const bool quoted = !raw.empty() && raw.front() == '"';
    std::stringstream ss(raw);
    std::string item;
    while (std::getline(ss, item, quoted ? ';' : ',')) items.push_back(trim(item));
    if (items.empty()) items.push_back("");
    if (index >= items.size()) return std::nullopt;
    std::string v = items[index];
    if (v.size() >= 2 && v.front() == '"' && v.back() == '"')
        return text(v.substr(1, v.size() - 2));
    if (const std::optional<double> d = parse_decimal(v)) return num(*d);
    return text(v);
}

class Context {
  public:
    Context(const Settings& s, const std::map<std::string, double>& runtime)
        : s_(s), runtime_(runtime) {}

    std::optional<Value> lookup(const std::string& name, size_t index) const {
        // Carve's own fields first: an option given on the command line overrides the profile.
        // The table's settings under their profile keys, and the few names PrusaSlicer
        // defines that carve fixes (one extruder) or states as printed (the first layer's
        // height, whose setting's 0 is the layer height).
        // A word (gcode_flavor, bed_shape) is the profile's own text, below: carve writes one
        // spelling for several of PrusaSlicer's ("marlin" and "marlin2" are both marlin2), and
        // a template tests the profile's. get() reads only numbers and switches.
        if (const SettingSpec* spec = find_setting_by_ini_key(name);
            spec && !spec->text() && !spec->prusa)
            return num(spec->get(s_));
        const std::map<std::string, double> fields = {
            {"first_layer_height", s_.first_layer_mm()},
            {"initial_tool", 0},
            {"initial_extruder", 0},
            {"current_extruder", 0},
        };
        if (auto it = fields.find(name); it != fields.end()) return num(it->second);
        if (auto it = runtime_.find(name); it != runtime_.end()) return num(it->second);
        if (auto it = s_.profile_values.find(name); it != s_.profile_values.end())
            return profile_element(it->second, index);
        return std::nullopt;
    }

  private:
    const Settings& s_;
    const std::map<std::string, double>& runtime_;
};

// Evaluates the inside of one {...} tag.
class Parser {
  public:
    Parser(const std::string& src, const Context& ctx) : s_(src), ctx_(ctx) {}

    Value whole() {
        Value v = logic_or();
        skip();
        if (i_ != s_.size()) fail("unexpected '" + s_.substr(i_) + "'");
        return v;
    }

  private:
    [[noreturn]] void fail(const std::string& why) const { throw Unresolved(why); }
    // One level of recursion; the parser refuses to go deeper than kMaxDepth.
    struct Level {
        explicit Level(Parser& p) : p_(p) {
            if (++p_.depth_ > kMaxDepth) p_.fail("expression nested too deeply");
        }
        ~Level() { --p_.depth_; }
        Parser& p_;
    };
    static Value checked_text(std::string s) {
        if (s.size() > kMaxString) throw Unresolved("string longer than 1 MB");
        return text(std::move(s));
    }
    void skip() {
        while (i_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[i_]))) ++i_;
    }
    bool eat(const std::string& tok) {
        skip();
        if (s_.compare(i_, tok.size(), tok) != 0) return false;
        // Word operators must not be the start of a longer identifier ("order" is not "or").
        if (std::isalpha(static_cast<unsigned char>(tok.back())) && i_ + tok.size() < s_.size() &&
            (std::isalnum(static_cast<unsigned char>(s_[i_ + tok.size()])) ||
             s_[i_ + tok.size()] == '_'))
            return false;
        i_ += tok.size();
        return true;
    }
    static double need_number(const Value& v) {
        if (!v.is_number) throw Unresolved("'" + v.text + "' is not a number");
        return v.number;
    }

    Value logic_or() {
        const Level level(*this);
        Value v = logic_and();
        while (eat("||") || eat("or")) {
            const Value r = logic_and();
            v = num(v.truthy() || r.truthy());
        }
        return v;
    }
    Value logic_and() {
        Value v = comparison();
        while (eat("&&") || eat("and")) {
            const Value r = comparison();
            v = num(v.truthy() && r.truthy());
        }
        return v;
    }
    Value comparison() {
        Value a = sum();
        if (eat("=~") || eat("!~")) {
            const bool negate = s_[i_ - 2] == '!';
            skip();
            if (i_ >= s_.size() || s_[i_] != '/') fail("expected /regex/");
            // The pattern ends at the first '/' that is not escaped.
            size_t end = i_ + 1;
            while (end < s_.size() && s_[end] != '/') end += s_[end] == '\\' ? 2 : 1;
            if (end >= s_.size()) fail("unterminated /regex/");
            try {
                const LinearRegex re(std::string_view(s_).substr(i_ + 1, end - i_ - 1));
                i_ = end + 1;
                return num(re.full_match(a.str()) != negate);
            } catch (const std::invalid_argument& e) {
                fail(e.what());
            }
        }
        for (const char* op : {"<=", ">=", "==", "!=", "<>", "<", ">"}) {
            if (!eat(op)) continue;
            const Value b = sum();
            const std::string o = op;
            if (o == "==" || o == "!=" || o == "<>") {
                const bool eq =
                    a.is_number && b.is_number ? a.number == b.number : a.str() == b.str();
                return num(o == "==" ? eq : !eq);
            }
            const double x = need_number(a), y = need_number(b);
            return num(o == "<" ? x < y : o == ">" ? x > y : o == "<=" ? x <= y : x >= y);
        }
        return a;
    }
    Value sum() {
        Value v = product();
        for (;;) {
            if (eat("+")) {
                const Value r = product();
                v = v.is_number && r.is_number ? num(v.number + r.number)
                                               : checked_text(v.str() + r.str());
            } else if (eat("-")) {
                const Value r = product();
                v = num(need_number(v) - need_number(r));
            } else {
                return v;
            }
        }
    }
    Value product() {
        Value v = unary();
        for (;;) {
            if (eat("*")) {
                v = num(need_number(v) * need_number(unary()));
            } else if (eat("/")) {
                const double d = need_number(unary());
                if (d == 0) fail("division by zero");
                v = num(need_number(v) / d);
            } else {
                return v;
            }
        }
    }
    Value unary() {
        const Level level(*this);
        if (eat("-")) return num(-need_number(unary()));
        if (eat("!") || eat("not")) return num(!unary().truthy());
        return primary();
    }
    Value primary() {
        skip();
        if (i_ >= s_.size()) fail("expression ends too early");
        const char c = s_[i_];
        if (c == '(') {
            ++i_;
            Value v = logic_or();
            if (!eat(")")) fail("expected ')'");
            return v;
        }
        if (c == '"') {
            const size_t end = s_.find('"', i_ + 1);
            if (end == std::string::npos) fail("unterminated string");
            Value v = text(s_.substr(i_ + 1, end - i_ - 1));
            i_ = end + 1;
            return v;
        }
        if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') {
            // Decimal only (std::stod read "0x10" as 16): digits, '.', an exponent.
            size_t end = i_;
            while (end < s_.size() &&
                   (std::isdigit(static_cast<unsigned char>(s_[end])) || s_[end] == '.' ||
                    ((s_[end] == 'e' || s_[end] == 'E') && end + 1 < s_.size() &&
                     (std::isdigit(static_cast<unsigned char>(s_[end + 1])) ||
                      ((s_[end + 1] == '-' || s_[end + 1] == '+') && end + 2 < s_.size() &&
                       std::isdigit(static_cast<unsigned char>(s_[end + 2])))))))
                end += (s_[end] == 'e' || s_[end] == 'E') ? 2 : 1;
            const std::optional<double> d =
                parse_decimal(std::string_view(s_).substr(i_, end - i_));
            if (!d) fail("bad number '" + s_.substr(i_, end - i_) + "'");
            i_ = end;
            return num(*d);
        }
        if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') {
            const size_t start = i_;
            while (i_ < s_.size() &&
                   (std::isalnum(static_cast<unsigned char>(s_[i_])) || s_[i_] == '_'))
                ++i_;
            const std::string name = s_.substr(start, i_ - start);
            if (name == "true") return num(1);
            if (name == "false") return num(0);
            if (eat("(")) return call(name);
            size_t index = 0;
            if (eat("[")) {
                const double d = need_number(logic_or());
                if (!eat("]")) fail("expected ']'");
                if (!(d >= 0 && d < 1e6)) fail("index out of range");
                index = static_cast<size_t>(d);
            }
            const std::optional<Value> v = ctx_.lookup(name, index);
            if (!v) fail("unknown variable '" + name + "'");
            return *v;
        }
        fail(std::string("unexpected '") + c + "'");
    }
    Value call(const std::string& name) {
        std::vector<Value> args;
        if (!eat(")")) {
            do args.push_back(logic_or());
            while (eat(","));
            if (!eat(")")) fail("expected ')'");
        }
        if ((name == "min" || name == "max") && args.size() == 2) {
            const double a = need_number(args[0]), b = need_number(args[1]);
            return num(name == "min" ? std::min(a, b) : std::max(a, b));
        }
        if (name == "int" && args.size() == 1) return num(std::trunc(need_number(args[0])));
        if (name == "round" && args.size() == 1) return num(std::round(need_number(args[0])));
        if (name == "abs" && args.size() == 1) return num(std::abs(need_number(args[0])));
        fail("unknown function '" + name + "'");
    }

    const std::string& s_;
    const Context& ctx_;
    size_t i_ = 0;
    int depth_ = 0;
};

constexpr char kBad = '\x01';  // marks output that holds an unexpanded placeholder

// Legacy [name] and [name_N] placeholders in literal text; other brackets stay as they are.
// Scanned by hand in one pass (a std::regex iterator recursed once per character).
std::string expand_brackets(const std::string& in, const Context& ctx,
                            std::vector<std::string>& unresolved) {
    auto ident_start = [](char c) {
        return std::isalpha(static_cast<unsigned char>(c)) || c == '_';
    };
    auto ident = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; };
    std::string out;
    size_t last = 0, line_start = 0;
    bool in_comment = false;
    for (size_t i = 0; i < in.size(); ++i) {
        if (in[i] == '\n') line_start = i + 1, in_comment = false;
        if (in[i] == ';') in_comment = true;
        if (in[i] != '[' || i + 1 >= in.size() || !ident_start(in[i + 1])) continue;
        size_t j = i + 1;
        while (j < in.size() && ident(in[j])) ++j;
        if (j >= in.size() || in[j] != ']') continue;
        const std::string name = in.substr(i + 1, j - i - 1);
        const std::string whole = in.substr(i, j - i + 1);
        out += in.substr(last, i - last);
        last = j + 1;
        std::optional<Value> v = ctx.lookup(name, 0);
        // [name_N]: element N of a list value.
        const size_t us = name.rfind('_');
        if (!v && us != std::string::npos && us + 1 < name.size() && us > 0 &&
            name.find_first_not_of("0123456789", us + 1) == std::string::npos &&
            name.size() - us - 1 <= 6)
            v = ctx.lookup(name.substr(0, us), std::stoul(name.substr(us + 1)));
        if (v) {
            out += v->str();
            check_expanded_size(out);
        } else if (in_comment) {
            out += whole;  // "; home [all]": harmless text for the firmware
        } else {
            unresolved.push_back(
                fmt::format("[{}]: unknown variable (line written as a comment)", name));
            out += kBad + whole;
        }
        i = j;
    }
    (void)line_start;
    return out + in.substr(last);
}

}  // namespace

std::string figure_beyond_range(const std::string& line) {
    const size_t b = line.find_first_not_of(" \t");
    if (b == std::string::npos || (line[b] != 'M' && line[b] != 'm')) return {};
    const std::string_view code_line = std::string_view(line).substr(b, line.find(';') - b);
    int code = -1;
    size_t i = 1;
    while (i < code_line.size() && std::isdigit(static_cast<unsigned char>(code_line[i]))) {
        code = std::max(code, 0) * 10 + (code_line[i] - '0');
        if (code > 1000) return {};
        ++i;
    }
    double limit = 0;
    const char* what = "";
    if (code == 104 || code == 109)
        limit = 450, what = "a nozzle temperature";
    else if (code == 140 || code == 190)
        limit = 150, what = "a bed temperature";
    else if (code == 106)
        limit = 255, what = "a fan speed";
    else
        return {};
    for (size_t k = i; k < code_line.size(); ++k) {
        const char c = code_line[k];
        if ((c != 'S' && c != 's' && c != 'R' && c != 'r') || (k > 0 && code_line[k - 1] != ' '))
            continue;
        size_t end = k + 1;
        while (end < code_line.size() && code_line[end] != ' ' && code_line[end] != '\t') ++end;
        const std::optional<double> v =
            parse_decimal(std::string(code_line.substr(k + 1, end - k - 1)));
        if (v && !(*v >= 0 && *v <= limit))
            return fmt::format("sets {} of {}, beyond 0 to {}", what, plain_number(*v),
                               plain_number(limit));
    }
    return {};
}

ExpandedGcode expand_custom_gcode(const std::string& text, const Settings& settings,
                                  const std::map<std::string, double>& runtime) {
    const Context ctx(settings, runtime);
    ExpandedGcode result;
    if (text.size() > kMaxText) {
        result.unresolved.push_back("custom G-code longer than 4 MB: not expanded");
        return result;
    }
    struct Branch {
        bool parent_active, active, taken;
    };
    std::vector<Branch> branches;
    auto active = [&] { return branches.empty() || branches.back().active; };
    auto condition = [&](const std::string& expr, const std::string& tag) {
        try {
            return Parser(expr, ctx).whole().truthy();
        } catch (const std::exception& e) {
            result.unresolved.push_back(
                fmt::format("{{{}}}: {} (taken as false)", shorten(tag), e.what()));
            return false;
        }
    };

    std::string out;
    size_t i = 0;
    while (i < text.size()) {
        const size_t open = text.find('{', i);
        const std::string literal =
            text.substr(i, open == std::string::npos ? std::string::npos : open - i);
        if (active()) out += expand_brackets(literal, ctx, result.unresolved);
        check_expanded_size(out);
        if (open == std::string::npos) break;
        const size_t close = text.find('}', open);
        if (close == std::string::npos) {
            result.unresolved.push_back("'{' without '}'");
            if (active()) out += kBad + text.substr(open);
            break;
        }
        const std::string tag = trim(text.substr(open + 1, close - open - 1));
        i = close + 1;
        if (tag.size() > kMaxTag) {
            result.unresolved.push_back("a {...} longer than 64 kB (taken as false / a comment)");
            if (tag.rfind("if", 0) == 0)
                branches.push_back({active(), false, false});
            else if (active())
                out += kBad;
            continue;
        }
        auto keyword = [&](const std::string& k) {
            return tag.rfind(k, 0) == 0 &&
                   (tag.size() == k.size() ||
                    std::isspace(static_cast<unsigned char>(tag[k.size()])));
        };
        if (keyword("if")) {
            const bool parent = active();
            const bool c = parent && condition(tag.substr(2), tag);
            branches.push_back({parent, parent && c, c});
        } else if (keyword("elsif")) {
            if (branches.empty()) {
                result.unresolved.push_back("{elsif} without {if}");
                continue;
            }
            Branch& b = branches.back();
            const bool c = b.parent_active && !b.taken && condition(tag.substr(5), tag);
            b.active = b.parent_active && !b.taken && c;
            b.taken = b.taken || c;
        } else if (tag == "else") {
            if (branches.empty()) {
                result.unresolved.push_back("{else} without {if}");
                continue;
            }
            Branch& b = branches.back();
            b.active = b.parent_active && !b.taken;
            b.taken = true;
        } else if (tag == "endif") {
            if (branches.empty())
                result.unresolved.push_back("{endif} without {if}");
            else
                branches.pop_back();
        } else if (active()) {
            try {
                out += Parser(tag, ctx).whole().str();
            } catch (const std::exception& e) {
                result.unresolved.push_back(
                    fmt::format("{{{}}}: {} (line written as a comment)", shorten(tag), e.what()));
                out += kBad + text.substr(open, close - open + 1);
            }
            check_expanded_size(out);
        }
    }
    if (!branches.empty()) result.unresolved.push_back("{if} without {endif}");

    // A line that still holds a placeholder goes out as a comment: a firmware would read
    // "M104 S[temperature]" as "M104 S0".
    std::stringstream lines(out);
    std::string line;
    while (std::getline(lines, line)) {
        // A figure beyond the machine's range that carve computed (M104 S{layer_num*1000}) is
        // refused; one the profile wrote as it stands is passed through, as PrusaSlicer does.
        if (const std::string beyond = figure_beyond_range(line); !beyond.empty()) {
            if (text.find(line) == std::string::npos)
                throw InputError(fmt::format("the profile's custom G-code computes '{}': {}",
                                             comment_text(line), beyond));
            result.notes.push_back(
                fmt::format("'{}' {} (written as the profile has it)", comment_text(line), beyond));
        }
        if (line.find(kBad) != std::string::npos) {
            std::erase(line, kBad);
            // A carriage return inside the line would end the comment on the firmware.
            result.text += comment_text("; carve: could not expand: " + line) + "\n";
        } else {
            result.text += line + "\n";
        }
    }
    return result;
}

}  // namespace carve

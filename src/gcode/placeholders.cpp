// Custom G-code expansion: a small recursive-descent evaluator for the subset of PrusaSlicer's
// macro language that printer profiles use (numbers, strings, vector indices, + - * /, min/max,
// comparisons, regex match, and/or/not, if/elsif/else/endif). Anything beyond it is reported,
// never guessed: the affected line becomes a comment.
#include "gcode/placeholders.hpp"

#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <optional>
#include <regex>
#include <sstream>
#include <stdexcept>

namespace carve {

namespace {

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
    try {
        size_t used = 0;
        const double d = std::stod(v, &used);
        if (used == v.size()) return num(d);
    } catch (const std::exception&) {
    }
    return text(v);
}

class Context {
  public:
    Context(const Settings& s, const std::map<std::string, double>& runtime)
        : s_(s), runtime_(runtime) {}

    std::optional<Value> lookup(const std::string& name, size_t index) const {
        // Carve's own fields first: an option given on the command line overrides the profile.
        const std::map<std::string, double> fields = {
            {"temperature", s_.nozzle_temperature},
            {"first_layer_temperature", s_.first_layer_nozzle_temperature},
            {"bed_temperature", s_.bed_temperature},
            {"first_layer_bed_temperature", s_.first_layer_bed_temperature},
            {"nozzle_diameter", s_.nozzle},
            {"filament_diameter", s_.filament_diameter},
            {"filament_density", s_.filament_density},
            {"layer_height", s_.layer_height},
            {"first_layer_height", s_.layer_height},
            {"travel_speed", s_.travel_speed},
            {"retract_length", s_.retract_length},
            {"retract_speed", s_.retract_speed},
            {"retract_lift", s_.z_hop},
            {"max_print_speed", s_.max_print_speed},
            {"initial_tool", 0},
            {"initial_extruder", 0},
            {"current_extruder", 0},
            {"z_offset", 0},
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
            const size_t end = s_.find('/', i_ + 1);
            if (end == std::string::npos) fail("unterminated /regex/");
            const std::regex re(s_.substr(i_ + 1, end - i_ - 1));
            i_ = end + 1;
            return num(std::regex_match(a.str(), re) != negate);
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
                v = v.is_number && r.is_number ? num(v.number + r.number) : text(v.str() + r.str());
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
            size_t used = 0;
            const double d = std::stod(s_.substr(i_), &used);
            i_ += used;
            return num(d);
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
                if (d < 0) fail("negative index");
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
};

constexpr char kBad = '\x01';  // marks output that holds an unexpanded placeholder

// Legacy [name] and [name_N] placeholders in literal text; other brackets stay as they are.
std::string expand_brackets(const std::string& in, const Context& ctx,
                            std::vector<std::string>& unresolved) {
    static const std::regex placeholder(R"(\[([A-Za-z_][A-Za-z0-9_]*)\])");
    std::string out;
    auto it = std::sregex_iterator(in.begin(), in.end(), placeholder);
    size_t last = 0;
    for (; it != std::sregex_iterator(); ++it) {
        const std::smatch& m = *it;
        out += in.substr(last, m.position(0) - last);
        last = m.position(0) + m.length(0);
        const std::string name = m[1];
        std::optional<Value> v = ctx.lookup(name, 0);
        static const std::regex indexed(R"((.*)_([0-9]+))");
        std::smatch im;
        if (!v && std::regex_match(name, im, indexed))
            v = ctx.lookup(im[1], static_cast<size_t>(std::stoul(im[2])));
        const size_t line_start = in.rfind('\n', m.position(0));
        const bool in_comment = in.find(';', line_start == std::string::npos ? 0 : line_start) <
                                static_cast<size_t>(m.position(0));
        if (v) {
            out += v->str();
        } else if (in_comment) {
            out += m.str(0);  // "; home [all]": harmless text for the firmware
        } else {
            unresolved.push_back(
                fmt::format("[{}]: unknown variable (line written as a comment)", name));
            out += kBad + m.str(0);
        }
    }
    return out + in.substr(last);
}

}  // namespace

ExpandedGcode expand_custom_gcode(const std::string& text, const Settings& settings,
                                  const std::map<std::string, double>& runtime) {
    const Context ctx(settings, runtime);
    ExpandedGcode result;
    struct Branch {
        bool parent_active, active, taken;
    };
    std::vector<Branch> branches;
    auto active = [&] { return branches.empty() || branches.back().active; };
    auto condition = [&](const std::string& expr, const std::string& tag) {
        try {
            return Parser(expr, ctx).whole().truthy();
        } catch (const std::exception& e) {
            result.unresolved.push_back(fmt::format("{{{}}}: {} (taken as false)", tag, e.what()));
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
        if (open == std::string::npos) break;
        const size_t close = text.find('}', open);
        if (close == std::string::npos) {
            result.unresolved.push_back("'{' without '}'");
            if (active()) out += kBad + text.substr(open);
            break;
        }
        const std::string tag = trim(text.substr(open + 1, close - open - 1));
        i = close + 1;
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
                    fmt::format("{{{}}}: {} (line written as a comment)", tag, e.what()));
                out += kBad + text.substr(open, close - open + 1);
            }
        }
    }
    if (!branches.empty()) result.unresolved.push_back("{if} without {endif}");

    // A line that still holds a placeholder goes out as a comment: a firmware would read
    // "M104 S[temperature]" as "M104 S0".
    std::stringstream lines(out);
    std::string line;
    while (std::getline(lines, line)) {
        if (line.find(kBad) != std::string::npos) {
            std::erase(line, kBad);
            result.text += "; carve: could not expand: " + line + "\n";
        } else {
            result.text += line + "\n";
        }
    }
    return result;
}

}  // namespace carve

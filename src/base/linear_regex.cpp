// Thompson-NFA regular expressions (see linear_regex.hpp): a recursive-descent parser into a
// small tree (recursion bounded by the nesting limit), code generation into instructions, and
// a simulation that keeps each instruction at most once per text position.
#include "base/linear_regex.hpp"

#include <cctype>
#include <memory>
#include <stdexcept>
#include <string>

namespace carve {

namespace {

constexpr size_t kMaxPattern = 4096;
constexpr int kMaxDepth = 64;
constexpr size_t kMaxProgram = 20000;
constexpr int kMaxRepeat = 1000;

struct Node {
    enum Kind { Atom, Concat, Alt, Repeat, Bol, Eol } kind = Concat;
    std::bitset<256> set;  // Atom
    std::vector<std::unique_ptr<Node>> kids;
    int min = 0, max = -1;  // Repeat; max -1 = unbounded
};

class Parser {
  public:
    explicit Parser(std::string_view p) : p_(p) {}

    std::unique_ptr<Node> whole() {
        auto n = alternation(0);
        if (i_ != p_.size()) fail("unmatched ')'");
        return n;
    }

  private:
    [[noreturn]] void fail(const std::string& why) const {
        throw std::invalid_argument("regex: " + why);
    }
    bool more() const { return i_ < p_.size(); }
    char peek() const { return p_[i_]; }

    std::unique_ptr<Node> alternation(int depth) {
        if (depth > kMaxDepth) fail("nested too deeply");
        auto alt = std::make_unique<Node>();
        alt->kind = Node::Alt;
        alt->kids.push_back(concatenation(depth));
        while (more() && peek() == '|') {
            ++i_;
            alt->kids.push_back(concatenation(depth));
        }
        if (alt->kids.size() == 1) return std::move(alt->kids[0]);
        return alt;
    }

    std::unique_ptr<Node> concatenation(int depth) {
        auto cat = std::make_unique<Node>();
        cat->kind = Node::Concat;
        while (more() && peek() != '|' && peek() != ')') {
            auto atom = atom_of(depth);
            // Postfix repetition; "a**" is repetition of a repetition, still linear.
            while (more() && (peek() == '*' || peek() == '+' || peek() == '?' || peek() == '{')) {
                int lo = 0, hi = -1;
                const char c = p_[i_++];
                if (c == '+') lo = 1;
                if (c == '?') hi = 1;
                if (c == '{') braces(lo, hi);
                if (atom->kind == Node::Bol || atom->kind == Node::Eol)
                    fail("repetition of an anchor");
                auto rep = std::make_unique<Node>();
                rep->kind = Node::Repeat;
                rep->min = lo, rep->max = hi;
                rep->kids.push_back(std::move(atom));
                atom = std::move(rep);
            }
            cat->kids.push_back(std::move(atom));
        }
        return cat;
    }

    int small_number() {
        int v = 0, digits = 0;
        while (more() && peek() >= '0' && peek() <= '9') {
            v = v * 10 + (p_[i_++] - '0');
            if (++digits > 4 || v > kMaxRepeat) fail("repetition count above 1000");
        }
        if (digits == 0) fail("expected a number in {}");
        return v;
    }

    void braces(int& lo, int& hi) {
        lo = small_number();
        hi = lo;
        if (more() && peek() == ',') {
            ++i_;
            hi = more() && peek() == '}' ? -1 : small_number();
        }
        if (!more() || p_[i_++] != '}') fail("expected '}'");
        if (hi >= 0 && hi < lo) fail("bad {n,m}");
    }

    static std::bitset<256> class_escape(char c, bool& known) {
        std::bitset<256> s;
        known = true;
        auto range = [&](int a, int b) {
            for (int k = a; k <= b; ++k) s.set(static_cast<size_t>(k));
        };
        switch (c) {
            case 'd':
                range('0', '9');
                break;
            case 'w':
                range('0', '9'), range('a', 'z'), range('A', 'Z'), s.set('_');
                break;
            case 's':
                for (char w : {' ', '\t', '\n', '\r', '\f', '\v'})
                    s.set(static_cast<unsigned char>(w));
                break;
            case 'D':
                s = class_escape('d', known).flip();
                break;
            case 'W':
                s = class_escape('w', known).flip();
                break;
            case 'S':
                s = class_escape('s', known).flip();
                break;
            case 'n':
                s.set('\n');
                break;
            case 't':
                s.set('\t');
                break;
            case 'r':
                s.set('\r');
                break;
            default:
                known = false;
                if (std::isalnum(static_cast<unsigned char>(c)))
                    throw std::invalid_argument(std::string("regex: unsupported escape \\") + c);
                s.set(static_cast<unsigned char>(c));
        }
        return s;
    }

    std::unique_ptr<Node> atom_of(int depth) {
        auto n = std::make_unique<Node>();
        n->kind = Node::Atom;
        const char c = p_[i_++];
        switch (c) {
            case '(': {
                if (i_ + 1 < p_.size() && peek() == '?') {
                    if (p_[i_ + 1] != ':')
                        fail("unsupported group (?" + std::string(1, p_[i_ + 1]));
                    i_ += 2;
                }
                auto inner = alternation(depth + 1);
                if (!more() || p_[i_++] != ')') fail("missing ')'");
                return inner;
            }
            case '[':
                bracket(n->set);
                return n;
            case '.':
                n->set.set();
                n->set.reset('\n');
                return n;
            case '^':
                n->kind = Node::Bol;
                return n;
            case '$':
                n->kind = Node::Eol;
                return n;
            case '\\': {
                if (!more()) fail("trailing '\\'");
                bool known = false;
                n->set = class_escape(p_[i_++], known);
                return n;
            }
            case '*':
            case '+':
            case '?':
            case '{':
                fail(std::string("nothing to repeat before '") + c + "'");
            default:
                n->set.set(static_cast<unsigned char>(c));
                return n;
        }
    }

    void bracket(std::bitset<256>& s) {
        bool negate = false;
        if (more() && peek() == '^') negate = true, ++i_;
        bool first = true;
        while (more() && (peek() != ']' || first)) {
            first = false;
            int lo;
            if (peek() == '\\' && i_ + 1 < p_.size()) {
                ++i_;
                bool known = false;
                const std::bitset<256> e = class_escape(p_[i_++], known);
                if (known) {
                    s |= e;
                    continue;
                }
                lo = static_cast<unsigned char>(p_[i_ - 1]);
            } else {
                lo = static_cast<unsigned char>(p_[i_++]);
            }
            int hi = lo;
            if (i_ + 1 < p_.size() && peek() == '-' && p_[i_ + 1] != ']') {
                ++i_;
                hi = static_cast<unsigned char>(p_[i_++]);
                if (hi < lo) fail("bad range in [...]");
            }
            for (int k = lo; k <= hi; ++k) s.set(static_cast<size_t>(k));
        }
        if (!more()) fail("missing ']'");
        ++i_;
        if (negate) s.flip();
    }

    std::string_view p_;
    size_t i_ = 0;
};

class Compiler {
  public:
    Compiler(std::vector<LinearRegex::Inst>& prog, std::vector<std::bitset<256>>& sets)
        : prog_(prog), sets_(sets) {}

    void emit(const Node& n) {
        if (prog_.size() > kMaxProgram) throw std::invalid_argument("regex: too large");
        switch (n.kind) {
            case Node::Atom:
                sets_.push_back(n.set);
                add({LinearRegex::Inst::Set, static_cast<int>(sets_.size() - 1), 0});
                break;
            case Node::Bol:
                add({LinearRegex::Inst::Bol});
                break;
            case Node::Eol:
                add({LinearRegex::Inst::Eol});
                break;
            case Node::Concat:
                for (const auto& k : n.kids) emit(*k);
                break;
            case Node::Alt: {
                std::vector<size_t> jumps;
                for (size_t i = 0; i < n.kids.size(); ++i) {
                    if (i + 1 < n.kids.size()) {
                        const size_t split = add({LinearRegex::Inst::Split});
                        prog_[split].x = here();
                        emit(*n.kids[i]);
                        jumps.push_back(add({LinearRegex::Inst::Jmp}));
                        prog_[split].y = here();
                    } else {
                        emit(*n.kids[i]);
                    }
                }
                for (size_t j : jumps) prog_[j].x = here();
                break;
            }
            case Node::Repeat: {
                const Node& e = *n.kids[0];
                for (int i = 0; i < n.min; ++i) emit(e);
                if (n.max < 0) {  // star
                    const size_t loop = add({LinearRegex::Inst::Split});
                    prog_[loop].x = here();
                    emit(e);
                    add({LinearRegex::Inst::Jmp, static_cast<int>(loop)});
                    prog_[loop].y = here();
                } else {
                    std::vector<size_t> splits;
                    for (int i = n.min; i < n.max; ++i) {
                        const size_t s = add({LinearRegex::Inst::Split});
                        prog_[s].x = here();
                        splits.push_back(s);
                        emit(e);
                    }
                    for (size_t s : splits) prog_[s].y = here();
                }
                break;
            }
        }
    }

  private:
    size_t add(LinearRegex::Inst inst) {
        prog_.push_back(inst);
        return prog_.size() - 1;
    }
    int here() const { return static_cast<int>(prog_.size()); }

    std::vector<LinearRegex::Inst>& prog_;
    std::vector<std::bitset<256>>& sets_;
};

}  // namespace

LinearRegex::LinearRegex(std::string_view pattern) {
    if (pattern.size() > kMaxPattern)
        throw std::invalid_argument("regex: longer than 4096 characters");
    const std::unique_ptr<Node> tree = Parser(pattern).whole();
    Compiler(prog_, sets_).emit(*tree);
    prog_.push_back({Inst::Match});
    if (prog_.size() > kMaxProgram) throw std::invalid_argument("regex: too large");
}

bool LinearRegex::full_match(std::string_view text) const {
    const size_t n = prog_.size();
    std::vector<int> current, next, stack;
    std::vector<size_t> mark(n, static_cast<size_t>(-1));
    current.reserve(n), next.reserve(n), stack.reserve(n);
    // Adds `pc` and everything reachable from it without reading a character, at position
    // `pos`; `gen` tells which list the marks belong to (two generations per position).
    auto add = [&](std::vector<int>& list, int start, size_t pos, size_t gen) {
        stack.push_back(start);
        while (!stack.empty()) {
            const int pc = stack.back();
            stack.pop_back();
            if (mark[pc] == gen) continue;
            mark[pc] = gen;
            const Inst& in = prog_[pc];
            switch (in.op) {
                case Inst::Jmp:
                    stack.push_back(in.x);
                    break;
                case Inst::Split:
                    stack.push_back(in.y), stack.push_back(in.x);
                    break;
                case Inst::Bol:
                    if (pos == 0) stack.push_back(pc + 1);
                    break;
                case Inst::Eol:
                    if (pos == text.size()) stack.push_back(pc + 1);
                    break;
                case Inst::Set:
                case Inst::Match:
                    list.push_back(pc);
                    break;
            }
        }
    };
    add(current, 0, 0, 0);
    for (size_t pos = 0; pos < text.size() && !current.empty(); ++pos) {
        const auto c = static_cast<unsigned char>(text[pos]);
        next.clear();
        for (int pc : current) {
            const Inst& in = prog_[pc];
            if (in.op == Inst::Set && sets_[in.x].test(c)) add(next, pc + 1, pos + 1, pos + 1);
        }
        std::swap(current, next);
    }
    for (int pc : current)
        if (prog_[pc].op == Inst::Match) return true;
    return false;
}

}  // namespace carve

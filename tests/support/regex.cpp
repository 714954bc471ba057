// The one instantiation of <regex> for all the test programs (regex.hpp).
#include "support/regex.hpp"

#include <regex>

namespace carve::test {

struct Regex::Compiled {
    std::regex re;
};

namespace {

void copy_groups(const std::smatch& m, std::vector<std::string>* groups) {
    if (!groups) return;
    groups->clear();
    for (const auto& g : m) groups->push_back(g.str());
}

}  // namespace

Regex::Regex(const std::string& pattern) : compiled_(new Compiled{std::regex(pattern)}) {}
Regex::Regex(Regex&&) noexcept = default;
Regex::~Regex() = default;

bool Regex::search(const std::string& text, std::vector<std::string>* groups) const {
    std::smatch m;
    if (!std::regex_search(text, m, compiled_->re)) return false;
    copy_groups(m, groups);
    return true;
}

bool Regex::match(const std::string& text, std::vector<std::string>* groups) const {
    std::smatch m;
    if (!std::regex_match(text, m, compiled_->re)) return false;
    copy_groups(m, groups);
    return true;
}

std::string Regex::replace(const std::string& text, const std::string& with) const {
    return std::regex_replace(text, compiled_->re, with);
}

}  // namespace carve::test

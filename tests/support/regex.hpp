// std::regex for the tests, compiled once in the test support library: instantiating <regex>
// costs about 3 s of compilation in every file that uses it, and eight test programs did, in
// both CI trees (bench/results/ci_time.md). Patterns are ECMAScript, as std::regex's default.
#pragma once

#include <memory>
#include <string>
#include <vector>

namespace carve::test {

class Regex {
  public:
    explicit Regex(const std::string& pattern);
    Regex(Regex&&) noexcept;
    ~Regex();

    // std::regex_search: somewhere in `text`. `groups` gets the match, then each group ("" for
    // one that took no part).
    bool search(const std::string& text, std::vector<std::string>* groups = nullptr) const;
    // std::regex_match: the whole of `text`.
    bool match(const std::string& text, std::vector<std::string>* groups = nullptr) const;
    // std::regex_replace: every match replaced by `with` ($1 for a group).
    std::string replace(const std::string& text, const std::string& with) const;

  private:
    struct Compiled;
    std::unique_ptr<Compiled> compiled_;
};

}  // namespace carve::test

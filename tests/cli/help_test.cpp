// The documentation of the command line: every option of `carve slice|info|check --help` states
// its default (a "[...]" marker) and, for a number, its unit; that default is the value in the
// code (the member a row of cli/options.hpp or the setting table binds); the man page
// docs/carve.1 covers every option with the same default and renders without groff warnings.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "base/numbers.hpp"
#include "cli/options.hpp"
#include "config/setting_table.hpp"
#include "support/carve_run.hpp"
#include "support/regex.hpp"

using carve::test::read;

namespace fs = std::filesystem;

namespace {

struct HelpEntry {
    std::string names;        // "-o,--output" or "model"
    std::string type;         // "TEXT", "FLOAT:FLOAT in [0.01 - 2]", "" for flags
    std::string description;  // joined over its wrapped lines
};

std::string output_of(const std::string& cmd, int* status = nullptr) {
    std::string out;
    FILE* p = popen(cmd.c_str(), "r");
    if (!p) return out;
    char buf[4096];
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
    const int raw = pclose(p);
    if (status) *status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    return out;
}

// CLI11's layout: "  NAMES TYPE   description", the description in a column of its own, on the
// next line when the names are long, and wrapped lines indented to that column.
std::vector<HelpEntry> parse_help(const std::string& text) {
    std::vector<HelpEntry> entries;
    std::stringstream in(text);
    std::string line;
    bool in_list = false;
    static const carve::test::Regex entry(R"(^  (\S+)(?: ((?:\S| (?=\S))+))?(?:\s{2,}(.*))?$)");
    while (std::getline(in, line)) {
        if (line == "Options:" || line == "Positionals:") {
            in_list = true;
            continue;
        }
        if (!in_list || line.empty()) continue;
        std::vector<std::string> m;
        if (line.size() > 10 && line.find_first_not_of(' ') >= 10 && !entries.empty()) {
            std::string& d = entries.back().description;
            d += (d.empty() ? "" : " ") + line.substr(line.find_first_not_of(' '));
        } else if (entry.match(line, &m)) {
            entries.push_back({m[1], m[2], m[3]});
        } else {
            ADD_FAILURE() << "unparsed help line: " << line;
        }
    }
    for (HelpEntry& e : entries) {
        // Flags print their negation default as "{false}" glued to the name.
        e.names = carve::test::Regex(R"(\{.*\}$)").replace(e.names, "");
        while (!e.description.empty() && e.description.back() == ' ') e.description.pop_back();
    }
    return entries;
}

std::vector<HelpEntry> help_of(const std::string& sub) {
    int status = -1;
    // Appended in steps: GCC 12 at -O1 warns of an out-of-bounds copy in the one-expression sum.
    std::string command = CARVE_BINARY;
    command += " " + sub + " --help";
    const std::string text = output_of(command, &status);
    EXPECT_EQ(status, 0) << sub;
    return parse_help(text);
}

std::string long_name(const std::string& names) {
    const size_t at = names.rfind("--");
    return at == std::string::npos ? names : names.substr(at);
}

std::string default_marker(const std::string& description) {
    std::vector<std::string> m;
    static const carve::test::Regex marker(R"((\[[^\[\]]+\])$)");
    return marker.search(description, &m) ? std::string(m[1]) : "";
}

const std::vector<std::string> kSubcommands = {"slice", "info", "check"};

// The .TP blocks of the man page with roff's escapes undone: "--layer-height MM ..." etc.
std::vector<std::string> man_blocks() {
    std::string man = read(fs::path(CARVE_SOURCE_DIR) / "docs" / "carve.1");
    std::vector<std::string> blocks;
    std::stringstream in(man);
    std::string line, block;
    bool open = false;
    auto close = [&] {
        if (open) blocks.push_back(block);
        block.clear();
        open = false;
    };
    while (std::getline(in, line)) {
        if (line.rfind(".TP", 0) == 0) {
            close();
            open = true;
            continue;
        }
        if (line.rfind(".SH", 0) == 0 || line.rfind(".SS", 0) == 0) {
            close();
            continue;
        }
        if (!open) continue;
        // Drop the macro names (.B, .BI, .BR) and the quotes of their arguments.
        line = carve::test::Regex(R"(^\.[A-Z]+ ?)").replace(line, "");
        line = carve::test::Regex("\"").replace(line, "");
        line = carve::test::Regex(R"(\\-)").replace(line, "-");
        block += line + " ";
    }
    close();
    return blocks;
}

}  // namespace

TEST(Help, EveryOptionStatesItsDefaultAndItsUnit) {
    static const carve::test::Regex unit(
        R"((^|[ ,(])(mm|mm2|mm/s|mm\^3/s|mm/s\^2|C|degrees|ratio|g/cm\^3|layers|lines|threads|vertices|voxels|copies|seconds|%|0/1)([ ;,)\[]|$))");
    int checked = 0;
    for (const std::string& sub : kSubcommands) {
        const std::vector<HelpEntry> entries = help_of(sub);
        EXPECT_GE(entries.size(), 3u) << sub;
        for (const HelpEntry& e : entries) {
            if (e.names == "-h,--help") continue;
            ++checked;
            EXPECT_NE(default_marker(e.description), "")
                << sub << " " << e.names << ": no [default] at the end of '" << e.description
                << "'";
            const bool number = e.type.rfind("FLOAT", 0) == 0 || e.type.rfind("INT", 0) == 0;
            if (number) {
                EXPECT_TRUE(unit.search(e.description))
                    << sub << " " << e.names << " (" << e.type << "): no unit in '" << e.description
                    << "'";
            }
        }
    }
    EXPECT_GT(checked, 50);  // the parser saw the options, it did not skip them
}

TEST(Help, ThePlainDescriptionsParse) {
    // The parser itself: a wrapped description and a flag with a negation default.
    const auto e = parse_help(
        "Options:\n  --a FLOAT:FLOAT in [1 - 2]\n                              Aaa, mm [1]\n"
        "  --keep{false}   Keep [off]\n  -q,--quiet                  Quiet\n");
    ASSERT_EQ(e.size(), 3u);
    EXPECT_EQ(e[0].description, "Aaa, mm [1]");
    EXPECT_EQ(e[1].names, "--keep");
    EXPECT_EQ(default_marker(e[2].description), "");
}

// Whether a help's marker ("[0.05]", "[0: eight spread ...]", "[the header's, else 1.75]")
// states `value` as the default.
bool states(const std::string& marker, const std::string& value) {
    const std::string open = "[" + value;
    if (marker.rfind(open, 0) == 0 && marker.size() > open.size() &&
        std::string("]: ,;").find(marker[open.size()]) != std::string::npos)
        return true;
    const std::string close = " " + value + "]";
    return marker.size() >= close.size() &&
           marker.compare(marker.size() - close.size(), close.size(), close) == 0;
}

// What a row's member holds in a command as constructed: "0.05", "40000", "linear", "off", "".
template <class Command>
std::string code_default(const carve::cli::OptionRow<Command>& row) {
    Command defaults;
    return std::visit(
        [](auto* member) -> std::string {
            using T = std::remove_pointer_t<decltype(member)>;
            if constexpr (std::is_same_v<T, bool>)
                return *member ? "on" : "off";
            else if constexpr (std::is_same_v<T, std::string>)
                return *member;
            else
                return carve::plain_number(static_cast<double>(*member));
        },
        row.target(defaults));
}

// Every row's default against its --help line, by the row's long name.
template <class Command>
void expect_rows_state_their_defaults(const std::string& sub,
                                      const std::vector<carve::cli::OptionRow<Command>>& rows,
                                      std::set<std::string>& seen) {
    std::map<std::string, std::string> marker_of;
    for (const HelpEntry& e : help_of(sub))
        marker_of[long_name(e.names)] = default_marker(e.description);
    for (const carve::cli::OptionRow<Command>& row : rows) {
        if (row.names == carve::cli::kSettingsHere) continue;
        const std::string name = long_name(row.names);
        seen.insert(sub + " " + name);
        ASSERT_TRUE(marker_of.count(name)) << sub << " " << name << " is not in --help";
        const std::string marker = marker_of[name], value = code_default(row);
        if (value.empty())  // a path or a name not given: "[none]", "[required]", or in words
            EXPECT_TRUE(marker.size() > 1 && !std::isdigit(static_cast<unsigned char>(marker[1])))
                << sub << " " << name << ": the help states " << marker
                << " but the code's default is empty";
        else
            EXPECT_TRUE(states(marker, value)) << sub << " " << name << ": the help states "
                                               << marker << " but the code's default is " << value;
    }
}

TEST(Help, EveryDefaultIsTheValueInTheCode) {
    EXPECT_TRUE(states("[0.05]", "0.05"));
    EXPECT_TRUE(states("[0: eight spread over the height]", "0"));
    EXPECT_TRUE(states("[the header's, else 1.75]", "1.75"));
    EXPECT_FALSE(states("[0.4]", "0"));
    EXPECT_FALSE(states("[0.05]", "0.06"));
    std::set<std::string> seen;
    expect_rows_state_their_defaults("slice", carve::cli::slice_rows(), seen);
    expect_rows_state_their_defaults("info", carve::cli::info_rows(), seen);
    expect_rows_state_their_defaults("check", carve::cli::check_rows(), seen);
    // The setting table's options (a switch's help speaks of giving it, "[off]": not given).
    const carve::Settings defaults;
    std::map<std::string, std::string> marker_of;
    for (const HelpEntry& e : help_of("slice"))
        marker_of[long_name(e.names)] = default_marker(e.description);
    for (const carve::SettingSpec& spec : carve::setting_table()) {
        if (!*spec.option) continue;
        const std::string name = std::string("--") + spec.option;
        seen.insert("slice " + name);
        if (spec.is_switch()) {  // "--wipe", "!--no-m73,--m73", "!--keep-all-bridges"
            std::stringstream names(spec.cli_switch_names());
            for (std::string n; std::getline(names, n, ',');)
                seen.insert("slice " + n.substr(n.find("--")));
            continue;
        }
        ASSERT_TRUE(marker_of.count(name)) << name << " is not in carve slice --help";
        // A number as the number (a 0/1 setting's help says "[1]"), a text as its text.
        const std::string value =
            spec.text() ? spec.text_value(defaults) : carve::plain_number(spec.get(defaults));
        EXPECT_TRUE(states(marker_of[name], value.empty() ? "none" : value))
            << "slice " << name << ": the help states " << marker_of[name]
            << " but the code's default is " << value;
    }
    // No option declared outside both tables, where its default would be restated by hand.
    for (const std::string& sub : kSubcommands)
        for (const HelpEntry& e : help_of(sub)) {
            const std::string name = long_name(e.names);
            if (name == "--help") continue;
            EXPECT_TRUE(seen.count(sub + " " + name))
                << sub << " " << e.names << " is a row of neither cli/options.hpp nor the table";
        }
}

TEST(ManPage, CoversEveryOptionWithTheSameDefault) {
    const std::vector<std::string> blocks = man_blocks();
    ASSERT_GT(blocks.size(), 40u);
    for (const std::string& sub : kSubcommands) {
        for (const HelpEntry& e : help_of(sub)) {
            const std::string name = long_name(e.names);
            if (name == "--help" || name.rfind("--", 0) != 0) continue;
            const std::string marker = default_marker(e.description);
            bool named = false, same_default = false;
            const carve::test::Regex word(
                "(^| )" + carve::test::Regex(R"([\^\$])").replace(name, "") + "( |,|$)");
            for (const std::string& b : blocks) {
                // The option's own block: its name opens the block (its heading line).
                if (!word.search(b.substr(0, b.find(' ', name.size() + 1)))) continue;
                named = true;
                if (!marker.empty() && b.find(marker) != std::string::npos) same_default = true;
            }
            EXPECT_TRUE(named) << sub << " " << name << " is missing from docs/carve.1";
            EXPECT_TRUE(same_default)
                << sub << " " << name << ": docs/carve.1 does not give the default " << marker;
        }
    }
}

TEST(ManPage, NamesNoOptionThatCarveDoesNotHave) {
    std::set<std::string> known;
    for (const std::string& sub : kSubcommands)
        for (const HelpEntry& e : help_of(sub)) known.insert(long_name(e.names));
    for (const std::string& b : man_blocks()) {
        std::vector<std::string> m;
        if (carve::test::Regex(R"(^(--[a-z][a-z0-9-]*))").search(b, &m)) {
            EXPECT_TRUE(known.count(m[1])) << m[1] << " is in docs/carve.1 but not in --help";
        }
    }
}

TEST(ManPage, RendersWithoutWarnings) {
    if (access("/usr/bin/groff", X_OK) != 0) GTEST_SKIP() << "groff is not installed";
    const fs::path man = fs::path(CARVE_SOURCE_DIR) / "docs" / "carve.1";
    int status = -1;
    // -ww: every warning; -z: no output, only the diagnostics (on stderr, captured here).
    const std::string diagnostics =
        output_of("/usr/bin/groff -man -ww -z " + man.string() + " 2>&1", &status);
    EXPECT_EQ(status, 0);
    EXPECT_EQ(diagnostics, "");
    // And through man(1) as a user reads it, at a narrow width that forces wrapping.
    if (access("/usr/bin/man", X_OK) == 0) {
        const std::string text =
            output_of("MANWIDTH=60 /usr/bin/man -l " + man.string() + " 2>&1 | col -b", &status);
        EXPECT_EQ(status, 0);
        EXPECT_NE(text.find("EXIT STATUS"), std::string::npos);
        EXPECT_NE(text.find("--raster-pixel"), std::string::npos);
        EXPECT_EQ(text.find("warning"), std::string::npos) << text;
    }
}

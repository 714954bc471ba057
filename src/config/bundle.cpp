// Sections, inheritance and selection of PrusaSlicer config bundles (see bundle.hpp).
// PrusaSlicer applies the parents of `inherits = a; b` in order, each over the one before, then
// the section's own keys; carve does the same, recursively, refusing cycles.
#include "config/bundle.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <istream>
#include <vector>

#include "base/error.hpp"

namespace carve {

namespace {

bool abstract_name(const std::string& name) {
    return name.size() >= 2 && name.front() == '*' && name.back() == '*';
}

struct Section {
    std::string kind, name;
    int line = 0;
    std::map<std::string, IniValue> keys;
};

using Sections = std::map<std::string, Section>;  // by name, within one kind

const char* const kKinds[] = {"printer", "filament", "print"};

class Resolver {
  public:
    Resolver(const std::string& path, const std::map<std::string, Sections>& kinds)
        : path_(path), kinds_(kinds) {}

    std::map<std::string, IniValue> resolve(const std::string& kind, const std::string& name) {
        std::vector<std::string> chain;
        return resolve(kind, name, chain);
    }

  private:
    std::map<std::string, IniValue> resolve(const std::string& kind, const std::string& name,
                                            std::vector<std::string>& chain) {
        // Each section once (a diamond of parents would otherwise be resolved exponentially
        // often), and a bounded depth: the vendor bundles go four levels deep.
        const std::string id = kind + ":" + name;
        if (auto done = resolved_.find(id); done != resolved_.end()) return done->second;
        const Section& s = kinds_.at(kind).at(name);
        if (chain.size() >= kMaxDepth)
            throw InputError(fmt::format("{}:{}: [{}:{}] inherits more than {} levels deep", path_,
                                         s.line, kind, name, kMaxDepth));
        chain.push_back(name);
        std::map<std::string, IniValue> out;
        if (auto it = s.keys.find("inherits"); it != s.keys.end()) {
            std::string list = it->second.value;
            size_t from = 0;
            while (from <= list.size()) {
                size_t semi = list.find(';', from);
                if (semi == std::string::npos) semi = list.size();
                std::string parent = trim_whitespace(list.substr(from, semi - from));
                if (parent.size() >= 2 && parent.front() == '"' && parent.back() == '"')
                    parent = parent.substr(1, parent.size() - 2);
                from = semi + 1;
                if (parent.empty()) continue;
                const Sections& same = kinds_.at(kind);
                if (!same.count(parent))
                    throw InputError(fmt::format(
                        "{}:{}: [{}:{}] inherits '{}', which is not a {} section of the bundle",
                        path_, it->second.line, kind, name, parent, kind));
                if (std::find(chain.begin(), chain.end(), parent) != chain.end()) {
                    std::string cycle;
                    for (auto c = std::find(chain.begin(), chain.end(), parent); c != chain.end();
                         ++c)
                        cycle += fmt::format("[{}:{}] -> ", kind, *c);
                    throw InputError(fmt::format("{}:{}: [{}:{}] inherits itself: {}[{}:{}]", path_,
                                                 it->second.line, kind, name, cycle, kind, parent));
                }
                for (auto& [k, v] : resolve(kind, parent, chain)) out[k] = v;
            }
        }
        for (const auto& [k, v] : s.keys)
            if (k != "inherits") out[k] = v;
        chain.pop_back();
        resolved_[id] = out;
        return out;
    }

    static constexpr size_t kMaxDepth = 64;
    const std::string& path_;
    const std::map<std::string, Sections>& kinds_;
    std::map<std::string, std::map<std::string, IniValue>> resolved_;
};

std::string names_of(const Sections& sections) {
    std::string out;
    for (const auto& [name, s] : sections)
        if (!abstract_name(name)) out += (out.empty() ? "" : ", ") + name;
    return out;
}

}  // namespace

std::string trim_whitespace(std::string s) {
    const char* ws = " \t\r\n";
    s.erase(0, s.find_first_not_of(ws));
    s.erase(s.find_last_not_of(ws) + 1);
    return s;
}

std::string first_quoted(const std::string& value) {
    if (value.empty() || value.front() != '"') return value;
    std::string out;
    for (size_t i = 1; i < value.size(); ++i) {
        if (value[i] == '\\' && i + 1 < value.size()) {
            out += value[i];
            out += value[++i];  // kept escaped: the reader unescapes \n, \" and \\ later
        } else if (value[i] == '"') {
            break;
        } else {
            out += value[i];
        }
    }
    return out;
}

ResolvedProfile read_ini_profile(std::istream& in, const std::string& path,
                                 const ProfileChoice& choice) {
    std::map<std::string, Sections> kinds;
    for (const char* k : kKinds) kinds[k];
    std::map<std::string, std::string> presets;  // [presets]
    std::map<std::string, IniValue> flat;        // every key, for a file without sections
    Section* current = nullptr;
    std::string current_kind;
    std::string line;
    int line_no = 0;
    while (std::getline(in, line)) {
        ++line_no;
        line = trim_whitespace(line);
        if (line.empty() || line[0] == '#' || line[0] == ';') continue;
        if (line[0] == '[') {
            if (line.back() != ']')
                throw InputError(fmt::format("{}:{}: expected '[section]'", path, line_no));
            const std::string header = line.substr(1, line.size() - 2);
            const size_t colon = header.find(':');
            current_kind = trim_whitespace(header.substr(0, colon));
            current = nullptr;
            if (colon != std::string::npos && kinds.count(current_kind)) {
                const std::string name = trim_whitespace(header.substr(colon + 1));
                Section& s = kinds[current_kind][name];
                s = Section{current_kind, name, line_no, {}};
                current = &s;
            }
            continue;
        }
        const size_t eq = line.find('=');
        if (eq == std::string::npos)
            throw InputError(fmt::format("{}:{}: expected 'key = value'", path, line_no));
        const std::string key = trim_whitespace(line.substr(0, eq));
        const std::string value = trim_whitespace(line.substr(eq + 1));
        if (current)
            current->keys[key] = IniValue{value, line_no, current->kind + ":" + current->name, ""};
        else if (current_kind == "presets")
            presets[key] = trim_whitespace(first_quoted(value));
        flat[key] = IniValue{value, line_no, "", ""};
    }

    ResolvedProfile out;
    for (const char* k : kKinds) out.bundle = out.bundle || !kinds[k].empty();
    // A choice that selects nothing was silently ignored: the run went on with other settings
    // than the user named.
    for (const char* kind : kKinds) {
        const std::string& given = kind == std::string("printer")    ? choice.printer
                                   : kind == std::string("filament") ? choice.filament
                                                                     : choice.print;
        if (!given.empty() && kinds[kind].empty())
            throw InputError(fmt::format(
                "{}: --{}-profile '{}' selects nothing: the file has no [{}:...] sections{}", path,
                kind, given, kind,
                out.bundle ? "" : " (a flat profile, as File > Export > Export Config writes)"));
    }
    if (!out.bundle) {
        out.values = std::move(flat);
        return out;
    }
    Resolver resolver(path, kinds);
    std::map<std::string, std::map<std::string, IniValue>> chosen;
    for (const char* kind : kKinds) {
        const Sections& sections = kinds[kind];
        if (sections.empty()) continue;
        const std::string& given = kind == std::string("printer")    ? choice.printer
                                   : kind == std::string("filament") ? choice.filament
                                                                     : choice.print;
        const std::string option = fmt::format("--{}-profile", kind);
        std::string name = given;
        if (name.empty() && presets.count(kind)) name = presets[kind];
        if (name.empty() && chosen.count("printer")) {
            // The vendor bundles name each printer's usual filament and print settings.
            const auto& printer = chosen["printer"];
            const auto it = printer.find(fmt::format("default_{}_profile", kind));
            if (it != printer.end()) {
                const std::string d = trim_whitespace(first_quoted(it->second.value));
                if (sections.count(d) && !abstract_name(d)) name = d;
            }
        }
        if (name.empty()) {
            std::vector<std::string> concrete;
            for (const auto& [n, s] : sections)
                if (!abstract_name(n)) concrete.push_back(n);
            if (concrete.size() == 1) name = concrete[0];
        }
        if (name.empty())
            throw InputError(fmt::format(
                "{}: the bundle's [presets] names no {} preset; choose one with {} NAME from: {}",
                path, kind, option, names_of(sections)));
        if (!sections.count(name))
            throw InputError(fmt::format("{}: no [{}:{}] in the bundle ({} NAME); it has: {}", path,
                                         kind, name, option, names_of(sections)));
        if (abstract_name(name))
            throw InputError(
                fmt::format("{}: [{}:{}] is abstract, a parent of other presets; choose one of: {}",
                            path, kind, name, names_of(sections)));
        chosen[kind] = resolver.resolve(kind, name);
        (kind == std::string("printer")    ? out.printer
         : kind == std::string("filament") ? out.filament
                                           : out.print) = name;
    }
    for (const char* kind : {"print", "filament", "printer"}) {
        const std::string& name = kind == std::string("printer")    ? out.printer
                                  : kind == std::string("filament") ? out.filament
                                                                    : out.print;
        for (auto& [k, v] : chosen[kind]) {
            out.values[k] = v;
            out.values[k].owner = fmt::format("{}:{}", kind, name);
        }
    }
    return out;
}

}  // namespace carve

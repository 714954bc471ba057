// The settings precedence (see resolve.hpp).
#include "config/resolve.hpp"

#include <algorithm>
#include <string_view>

#include "base/error.hpp"
#include "config/presets.hpp"

namespace carve {

ResolvedSettings resolve_settings(const GivenSettings& given,
                                  const std::function<double()>& model_slenderness) {
    ResolvedSettings out;
    Settings& settings = out.settings;
    if (given.printer) apply_printer_preset(*given.printer, settings);
    const ProfileChoice& choice = given.profile.choice;
    if (given.profile_path.empty() && (!choice.printer.empty() || !choice.filament.empty() ||
                                       !choice.print.empty() || given.profile.profile_shells))
        throw UsageError(
            "--printer-profile, --filament-profile, --print-profile and --profile-shells need "
            "--load");
    if (!given.profile_path.empty())
        out.notes = load_prusa_profile(given.profile_path, settings, given.profile);
    if (!given.preset.empty()) apply_print_preset(given.preset, settings);
    for (const auto& [spec, text] : given.options)
        spec->set(settings, text, std::string("--") + spec->option);
    // --strong moves shells and ties, but not those typed on the command line. The split
    // between them follows the model's slenderness, which no scale changes.
    const auto typed = [&given](std::string_view option) {
        return std::any_of(given.options.begin(), given.options.end(),
                           [&](const auto& g) { return option == g.first->option; });
    };
    const double slender = settings.strength > 0 ? model_slenderness() : 0;
    apply_strength(settings, slender, typed("shells"), typed("ties"));
    // Only once every option is in: --carving may come after an option of its scheme.
    for (const auto& option : given.options) check_scheme(*option.first, settings);
    return out;
}

}  // namespace carve

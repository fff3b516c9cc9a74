// One vocabulary for every front: the same keys configure `wavecam apply` (as --KEY flags),
// the OIIO plugin (as `--iconfig wavecam:KEY VALUE` hints or `?KEY=VALUE` in the name),
// description files (as TOML keys) and a source render's own `wavecam.KEY` metadata. Values are
// text with units, as a person types them.
#pragma once
#include <OpenImageIO/imageio.h>

#include <functional>
#include <map>
#include <string>
#include <vector>
#include "wavecam/diffract_image.h"
#include "wavecam/result.h"

namespace wavecam::front {

using Settings = std::map<std::string, std::string>;

// One setting: its key, an example value (for messages), a one-line description (for help),
// whether a source's metadata may give it, and how its text sets the options ("NAME" words errors).
struct SettingKey {
    std::string key, example, help;
    bool from_source;
    Result<bool> (*apply)(const std::string& text, const std::string& name, DiffractOptions& options);
};
const std::vector<SettingKey>& setting_keys();

// A film distance (pinhole to film) of 0.1mm or more; errors name `name` ("film-distance:
// expected ..."). Every front's --film-distance.
Result<double> parse_film_distance(const std::string& text, const std::string& name);

// Where settings come from. One order for every front, lowest first (docs/settings.md "One
// order"): built-in defaults < the source's `wavecam.KEY` metadata < a description file < what
// the user gave (the command's flags; the plugin's --iconfig hints, then ?KEY=VALUE).
struct SettingSources {
    Settings given;                // what the user gave this run
    Settings description;          // a description file's keys
    std::string description_path;  // names them in errors
    // How this front names a key the user gave: "--fov", "?fov= in the name", "--iconfig wavecam:fov".
    std::function<std::string(const std::string& key)> given_name;
};

struct ResolvedSettings {
    DiffractOptions options;
    Settings text;  // every setting in force, from every layer, as text: the same text, the same options
    // One line per old spelling taken ("--method: 'fast' is now called 'convolution'"): the front
    // shows them once.
    std::vector<std::string> notes;
};

// Resolves the settings of one source render, every value checked once. The source's metadata
// gives every key but fov (its wavecam.fov is read by load_render, in any type), the limits
// max-terms and max-memory (a file cannot lift what protects the machine) and input-colorspace
// (its oiio:ColorSpace says that, or for a file wavecam wrote, its wavecam.output-colorspace). Errors read "NAME: what was expected, got 'VALUE'", NAME as
// the user gave the key ("--pinhole", "wavecam.pinhole", "shot.wavecam: pinhole"); an unknown
// key lists the known ones.
Result<ResolvedSettings> resolve_settings(const OIIO::ImageSpec& source, const SettingSources& sources);

// The setting key nearest to a mistyped one ("pinhol", "film_distance"), "" when none is near.
std::string nearest_key(const std::string& unknown);
// "NAME: unknown key; did you mean 'pinhole'? (known: ...)": every route's refusal of a key it
// does not know (a typo never falls back to a default).
std::string unknown_key_message(const std::string& name, const std::string& key);

// Prints each note to standard error once per process ("wavecam: --method: 'fast' is now called
// 'convolution'"): a sequence or a host that opens many files hears it once.
void show_notes(const std::vector<std::string>& notes);

// The fronts, for wording what core reports.
enum class Front { Command, Plugin };

// A core failure in this front's words: a missing setting gets how to give it, a job beyond a
// limit how to get under it, an unusable value the setting's name.
std::string word_failure(const Result<bool>& failure, Front front);

}  // namespace wavecam::front

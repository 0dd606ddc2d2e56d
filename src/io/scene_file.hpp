#pragma once
// Scene files: JSON read into a SceneDesc with every field checked, "--set" overrides, and
// the resolved scene written back out. docs/scenes.md documents the format.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "sim/scene_desc.hpp"

namespace weft {

// The viewer's display switches, as "--show" and a scene's "view": {"show": [...]} name them
// (each "no-" switch turns its partner off; later ones win).
extern const std::vector<std::string> display_switch_names;

// Reads a scene document. `file` names it in errors. Unknown keys, wrong types and values out
// of range throw SceneError with the JSON pointer of the offending field.
SceneDesc parse_scene(const nlohmann::json& document, const std::string& file);

// Parses a scene file's text (JSON), applies the overrides, then parses the scene; `file` names it
// in errors, except those in a part an override wrote, which name the override. load_scene_file
// reads the file and calls this. Throws SceneError.
SceneDesc parse_scene_text(const std::string& text, const std::string& file,
                           const std::vector<std::string>& overrides = {});

// Reads the file, applies overrides of the form "path=value" (path: dots or a JSON pointer,
// value: JSON, or a bare string), then parses. Throws SceneError.
SceneDesc load_scene_file(const std::string& path, const std::vector<std::string>& overrides = {});

// Applies one "path=value" override to a document; throws SceneError naming the override
// ("--set path=value"). Returns the JSON pointer of the part the override wrote: its path, or the
// first member on it that the document did not have (which the override created).
std::string apply_override(nlohmann::json& document, const std::string& assignment);

// `error` as the error of the last of `overrides` that sets the part of the scene it is in
// ("--set path=value: /path: ..."), for errors found once the scene is read (build_world's);
// any other error as it is.
SceneError naming_override(const SceneError& error, const std::vector<std::string>& overrides);

// The scene with every field written out (defaults included); parse_scene reads it back.
nlohmann::json scene_to_json(const SceneDesc& scene);

// A resolved scene without what does not change the simulation (its "view"): what a resumed run
// or a sweep case compares with the recorded scene.
nlohmann::json simulated_part(nlohmann::json resolved_scene);

}  // namespace weft

// pnb_editor/set_expression.h — the editor's batch edit `--set 'MATERIAL.FIELD=VALUE'`.
//
// MATERIAL is a wildcard pattern over material names (globMatch), FIELD a material_fields.h
// name, VALUE its text form. Material names may contain dots, so the field is the part after
// the LAST dot before the '='.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "pnb/error.h"
#include "pnb/scene.h"

namespace pnb::editor {

struct SetExpression {
    std::string pattern, field, value;
};

// Parses "PATTERN.FIELD=VALUE". Errors (BadReference) say what is missing and show the form.
Result<SetExpression> parseSetExpression(std::string_view text);

// Applies `expr` to every material of `scene` whose name matches. Returns how many matched;
// an error (and no change to any material) if none matches — listing the names — or if the field
// or value is invalid.
Result<size_t> applySetExpression(Scene& scene, const SetExpression& expr);

} // namespace pnb::editor

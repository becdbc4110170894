#include "pnb_editor/set_expression.h"

#include "pnb/material_fields.h"

namespace pnb::editor {

Result<SetExpression> parseSetExpression(std::string_view text) {
    size_t eq = text.find('=');
    size_t dot = eq == std::string_view::npos ? std::string_view::npos : text.rfind('.', eq);
    if (eq == std::string_view::npos || dot == std::string_view::npos || dot == 0 ||
        dot + 1 == eq)
        return makeError(FormatError::BadReference, 0,
                         "'%.*s' is not of the form MATERIAL.FIELD=VALUE (e.g. "
                         "'glass*.shading_path=forward')",
                         int(text.size()), text.data());
    return SetExpression{std::string(text.substr(0, dot)),
                         std::string(text.substr(dot + 1, eq - dot - 1)),
                         std::string(text.substr(eq + 1))};
}

Result<size_t> applySetExpression(Scene& scene, const SetExpression& expr) {
    std::vector<Material> edited = scene.materials;
    size_t matched = 0;
    for (Material& m : edited) {
        if (!globMatch(expr.pattern, scene.str(m.name))) continue;
        if (Status s = setMaterialField(m, expr.field, expr.value); !isOk(s)) return s;
        ++matched;
    }
    if (matched == 0) {
        std::string names;
        for (const Material& m : scene.materials)
            names += std::string(names.empty() ? "" : ", ") + std::string(scene.str(m.name));
        return makeError(FormatError::BadReference, 0, "no material matches '%s'; materials: %s",
                         expr.pattern.c_str(), names.empty() ? "(none)" : names.c_str());
    }
    scene.materials = std::move(edited);
    return matched;
}

} // namespace pnb::editor

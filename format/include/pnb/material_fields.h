// pnb/material_fields.h — every editable material field, described once (docs/STYLE.md §8).
//
// The table drives the converter's per-material sidecar overrides, the editor's command line
// (`--set MATERIAL.FIELD=VALUE`, `--list`) and its widgets; serialisation is chunks.h's. Field
// names are stable snake_case: they are part of the command-line and sidecar interfaces. It lives
// in the format library because every tool that edits a Material shares it (no GL, no UI).
#pragma once

#include <span>
#include <string>
#include <string_view>

#include "pnb/chunks.h"
#include "pnb/error.h"

namespace pnb {

enum class FieldType : uint8_t {
    Float,      // one number in [min, max]
    Color3,     // "r,g,b", each in [min, max]
    Color4,     // "r,g,b,a", each in [min, max]
    Bool,       // true|false
    Choice,     // one of `choices`
    Integer,    // whole number in [min, max]
    TextureRef, // TEXR index or "none"
};

// Where a field lives in one Material: the pointer its type uses, the others null.
struct MaterialFieldSlot {
    float* floats = nullptr; // Float, Color3, Color4: the first component (the rest follow it)
    bool* flag = nullptr;    // Bool
    uint8_t* choice = nullptr;    // Choice: the enum's byte
    uint16_t* integer = nullptr;  // Integer
    uint32_t* texture = nullptr;  // TextureRef
};

struct MaterialField {
    const char* name;
    FieldType type;
    float min, max;
    const char* choices; // Choice only: "|"-separated, in enum order
    const char* help;
    // The field's storage in `material`: each row carries its own, so the table is the one list
    // of fields (no second, positional list to keep in step).
    MaterialFieldSlot (*slot)(Material& material);
};

// All fields, in display order.
std::span<const MaterialField> materialFields();

// Sets `field` from text. Errors (BadReference, with a message that lists what is valid): an
// unknown field name, or a value that does not parse or is out of range. `material` is left
// unchanged on error.
Status setMaterialField(Material& material, std::string_view field, std::string_view value);

// The field's value as text, in the form setMaterialField accepts. Precondition: a valid name.
std::string getMaterialField(const Material& material, std::string_view field);

// Shell-style wildcard match of a material name: '*' matches any run (also empty), '?' one byte,
// everything else itself. Used by sidecar files and batch edits ("glass*", "*_trunk").
bool globMatch(std::string_view pattern, std::string_view text);

} // namespace pnb

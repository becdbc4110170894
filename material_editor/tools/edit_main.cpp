// pnb-edit: the material editor. With batch options it edits a container's materials without a
// window, through the same pnb::editor::Document the GUI uses; without them it starts the GUI
// (gui.h). Only argument parsing and printing live here; the option table below (pnb_cli) is the
// single description of the options and prints --help.
//
// Batch mode is all or nothing: every import and every --set must succeed (one undo step in the
// document, one atomic save) or the file is not touched.

#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "gui.h"
#include "pnb/material_fields.h"
#include "pnb/output_guard.h"
#include "pnb_cli/options.h"
#include "pnb_converter/memory_budget.h"
#include "pnb_editor/document.h"
#include "pnb_editor/set_expression.h"

namespace {

using pnb::editor::Document;

constexpr int kExitOk = 0, kExitUsage = 1, kExitInput = 2, kExitUnsupported = 3,
              kExitOutput = 4, kExitBusy = 5;

struct Import {
    std::string name, image;
    bool srgb = true;
};

struct Settings {
    std::string input;
    std::string output; // "" = in place
    bool list = false, json = false, quiet = false;
    std::vector<std::string> sets;
    std::vector<Import> imports;
    uint64_t maxMemory = 0; // 0 = the converter's default
    double lockTimeout = 60; // seconds to wait for another program saving the file

    bool batch() const { return list || !sets.empty() || !imports.empty() || !output.empty(); }
};

bool parseImport(const char* text, Import& out) {
    std::string_view a = text;
    size_t eq = a.find('=');
    if (eq == std::string_view::npos || eq == 0 || eq + 1 == a.size()) return false;
    out.name = std::string(a.substr(0, eq));
    std::string_view image = a.substr(eq + 1);
    out.srgb = true;
    if (image.size() > 5 && image.substr(image.size() - 5) == ":srgb") {
        image.remove_suffix(5);
    } else if (image.size() > 7 && image.substr(image.size() - 7) == ":linear") {
        image.remove_suffix(7);
        out.srgb = false;
    }
    out.image = std::string(image);
    return true;
}

// Declarative option table (pnb_cli): it parses the command line and prints --help (docs/STYLE.md §7).
std::vector<pnb::cli::Option> options(Settings& s, bool& help) {
    using pnb::cli::flag;
    using pnb::cli::valued;
    return {
        valued("Batch edits", "--set", "MATERIAL.FIELD=VALUE",
             "set a field of every material whose name matches MATERIAL ('*' and '?' wildcards), "
             "e.g. 'glass*.shading_path=forward'; repeatable. All --set options are one edit: all "
             "apply or none does. Texture fields take a texture name, an index or none",
             [&s](const char* a) { s.sets.push_back(a); return true; }),
        valued("Batch edits", "--import-texture", "NAME=IMAGE[:srgb|:linear]",
             "import an image file (PNG, JPEG, TGA, EXR, ...) as texture NAME, processed as "
             "pnb-convert does (mips, no compression); :srgb (default) for colour, :linear for "
             "normal, metallic-roughness and occlusion maps. Repeatable; applied before --set",
             [&s](const char* a) {
                 Import i;
                 if (!parseImport(a, i)) return false;
                 s.imports.push_back(i);
                 return true;
             }),
        valued("Batch edits", "--max-memory", "SIZE",
             "memory an imported texture may use while it is decoded and mip-mapped, e.g. 512M or "
             "2G; an image whose header declares more is refused before it is read (default: half "
             "of the memory this process may use)",
             [&s](const char* a) {
                 std::optional<uint64_t> bytes = pnb::converter::parseByteSize(a);
                 s.maxMemory = bytes.value_or(0);
                 return bytes.has_value();
             }),
        valued("Batch edits", "-o, --output", "FILE",
             "write the result here (default: replace SCENE.pnb in place, atomically)",
             [&s](const char* a) { s.output = a; return !s.output.empty(); }),
        valued("Batch edits", "--lock-timeout", "SECONDS",
             "how long to wait while another program saves the file (default 60). An edit in place "
             "holds the file's lock from reading it to replacing it, so concurrent edits queue "
             "instead of overwriting each other; past the wait, exit 5 with nothing written",
             [&s](const char* a) {
                 char* end = nullptr;
                 s.lockTimeout = std::strtod(a, &end);
                 return end != a && *end == '\0' && std::isfinite(s.lockTimeout) &&
                        s.lockTimeout >= 0;
             }),
        flag("Listing", "--list",
             "print every material with every field, the deferred layer order and the textures "
             "(after the edits, if any)",
             [&s](const char*) { s.list = true; return true; }),
        flag("Listing", "--json", "with --list: one JSON object instead of text",
             [&s](const char*) { s.json = true; return true; }),
        flag("General", "-q, --quiet", "print errors only",
             [&s](const char*) { s.quiet = true; return true; }),
        flag("General", "-h, --help", "print this help and exit", [&help](const char*) {
            help = true;
            return pnb::cli::Verdict::stopHere();
        }),
    };
}

void printHelp(std::FILE* f, const std::vector<pnb::cli::Option>& table) {
    std::fprintf(f,
                 "usage: pnb-edit SCENE.pnb [--list [--json]] [--set MATERIAL.FIELD=VALUE ...]\n"
                 "                [--import-texture NAME=IMAGE ...] [-o OUT.pnb] [-q]\n"
                 "       pnb-edit SCENE.pnb          (no batch option: the editor window)\n"
                 "       pnb-edit SCENE.pnb --ui-set MATERIAL.FIELD=VALUE ... [--ui-save-as OUT.pnb]\n"
                 "                [--ui-external CMD] [--ui-on-change reload|merge|merge-mine|save-as|keep]\n"
                 "                [--ui-save]  (another program changes the file; the prompt's answer)\n"
                 "                [--ui-frames N] [--ui-screenshot FILE.png] [--ui-size WxH]\n"
                 "                [--ui-check-labels]  (exit 4 if a property label is cut off)\n"
                 "                (a scripted window session through the widgets' own actions)\n\n"
                 "Edits the materials of a Penumbra container. A save rewrites only the string\n"
                 "table, the edited materials and what they newly need (programs, textures);\n"
                 "every other chunk is copied byte for byte.\n");
    // The material fields as help-only rows, laid out as the options are.
    std::vector<pnb::cli::Option> rows = table;
    std::vector<std::string> fieldHelp; // the rows' text lives here
    fieldHelp.reserve(pnb::materialFields().size());
    for (const pnb::MaterialField& mf : pnb::materialFields()) {
        std::string kind;
        char range[64];
        std::snprintf(range, sizeof(range), " in [%g, %g]", mf.min, mf.max);
        switch (mf.type) {
        case pnb::FieldType::Float: kind = std::string("number") + range; break;
        case pnb::FieldType::Color3: kind = std::string("r,g,b") + range; break;
        case pnb::FieldType::Color4: kind = std::string("r,g,b,a") + range; break;
        case pnb::FieldType::Bool: kind = "true|false"; break;
        case pnb::FieldType::Choice: kind = mf.choices; break;
        case pnb::FieldType::Integer: kind = std::string("whole number") + range; break;
        case pnb::FieldType::TextureRef: kind = "texture name, index or none"; break;
        }
        fieldHelp.push_back(mf.type == pnb::FieldType::TextureRef ? kind : kind + ": " + mf.help);
        rows.push_back({"Material fields (FIELD)", mf.name, "", fieldHelp.back(), nullptr});
    }
    std::fputs(pnb::cli::helpText(rows, {.column = 34, .wrapAt = 100, .longNameOwnLine = true}).c_str(), f);
    std::fprintf(f,
                 "\nExit codes:\n"
                 "  %d  ok\n"
                 "  %d  usage error (unknown option, malformed argument, missing SCENE.pnb)\n"
                 "  %d  input error (unreadable scene or image, unknown material or field, "
                 "invalid value);\n"
                 "     the file is not touched\n"
                 "  %d  unsupported (a newer format or chunk version than this build reads)\n"
                 "  %d  output error (the result could not be written; the file is not "
                 "touched)\n"
                 "  %d  busy: another program kept the file locked past --lock-timeout, or\n"
                 "     replaced it during the edit; the file is not touched, run again\n",
                 kExitOk, kExitUsage, kExitInput, kExitUnsupported, kExitOutput, kExitBusy);
}

int usageError(const std::string& message) {
    std::fprintf(stderr, "Error: %s (see --help)\n", message.c_str());
    return kExitUsage;
}

bool isBusy(const pnb::Error& e) {
    return e.code == pnb::FormatError::Locked || e.code == pnb::FormatError::ChangedOnDisk;
}

int inputError(const pnb::Error& e) {
    std::fprintf(stderr, "Error: %s\n", e.message.c_str());
    if (isBusy(e)) return kExitBusy;
    return e.code == pnb::FormatError::UnsupportedVersion ||
                   e.code == pnb::FormatError::UnsupportedChunkVersion
               ? kExitUnsupported
               : kExitInput;
}

// [SECTION] printing

// Names from the file, made safe for a terminal: control bytes become '?'.
std::string printable(std::string_view s) {
    std::string out(s);
    for (char& c : out)
        if ((unsigned char)c < 0x20 || c == 0x7F) c = '?';
    return out;
}

// A JSON string literal; invalid UTF-8 becomes U+FFFD, so a hostile file cannot break the JSON.
std::string jsonString(std::string_view s) {
    std::string out = "\"";
    for (size_t i = 0; i < s.size();) {
        unsigned char c = (unsigned char)s[i];
        if (c < 0x80) {
            if (c == '"' || c == '\\') out += '\\', out += char(c);
            else if (c < 0x20) {
                char buf[8];
                std::snprintf(buf, sizeof(buf), "\\u%04x", c);
                out += buf;
            } else out += char(c);
            ++i;
            continue;
        }
        size_t n = c >= 0xF0 && c < 0xF5 ? 4 : c >= 0xE0 ? 3 : c >= 0xC2 && c < 0xE0 ? 2 : 0;
        bool ok = n > 0 && i + n <= s.size();
        for (size_t k = 1; ok && k < n; ++k) ok = ((unsigned char)s[i + k] & 0xC0) == 0x80;
        if (ok && n == 3) { // no overlongs or surrogates
            unsigned char c1 = (unsigned char)s[i + 1];
            ok = !(c == 0xE0 && c1 < 0xA0) && !(c == 0xED && c1 >= 0xA0);
        }
        if (ok && n == 4) {
            unsigned char c1 = (unsigned char)s[i + 1];
            ok = !(c == 0xF0 && c1 < 0x90) && !(c == 0xF4 && c1 >= 0x90);
        }
        if (ok) {
            out.append(s.substr(i, n));
            i += n;
        } else {
            out += "\xEF\xBF\xBD";
            ++i;
        }
    }
    return out + "\"";
}

// A number list from getMaterialField as JSON: non-finite values become null.
std::string jsonNumbers(std::string_view text, bool array) {
    std::string out = array ? "[" : "";
    size_t start = 0;
    while (true) {
        size_t comma = text.find(',', start);
        std::string part(text.substr(start, comma == std::string_view::npos ? comma : comma - start));
        double v = std::strtod(part.c_str(), nullptr);
        out += std::isfinite(v) ? part : "null";
        if (comma == std::string_view::npos) break;
        out += ", ";
        start = comma + 1;
    }
    return array ? out + "]" : out;
}

const char* formatName(pnb::TextureFormat f) {
    static constexpr const char* kNames[] = {"r8",    "rg8",   "rgb8",  "rgba8", "r16f",
                                             "rg16f", "rgba16f", "r32f", "rg32f", "rgba32f",
                                             "bc1",   "bc3",   "bc4",   "bc5",   "bc7"};
    return size_t(f) < std::size(kNames) ? kNames[size_t(f)] : "?";
}

std::string programText(const pnb::Scene& scene, uint32_t program) {
    if (program == pnb::kNone) return "none";
    const pnb::Program& p = scene.programs[program];
    std::string s = std::to_string(program) + " " + printable(scene.str(p.name)) + "[";
    for (size_t i = 0; i < p.defines.size(); ++i)
        s += (i ? " " : "") + printable(scene.str(p.defines[i]));
    return s + "]";
}

void listText(const Document& doc, std::FILE* out) {
    const pnb::Scene& scene = doc.scene();
    std::fprintf(out, "%s: %zu materials, %zu textures, %zu programs\n",
                 printable(doc.path()).c_str(), doc.materialCount(), scene.textures.size(),
                 scene.programs.size());
    for (uint32_t i = 0; i < doc.materialCount(); ++i) {
        const pnb::Material& m = scene.materials[i];
        std::fprintf(out, "\nmaterial %u '%s'  (program %s)\n", i,
                     printable(doc.materialName(i)).c_str(), programText(scene, m.program).c_str());
        for (const pnb::MaterialField& f : pnb::materialFields()) {
            std::string value = pnb::getMaterialField(m, f.name);
            if (f.type == pnb::FieldType::TextureRef && value != "none")
                value += " (" + printable(scene.str(scene.textures[std::stoul(value)].name)) + ")";
            std::fprintf(out, "  %-28s = %s\n", f.name, value.c_str());
        }
    }
    auto names = [&](const std::vector<uint32_t>& list) {
        std::string s;
        for (uint32_t i : list) s += (s.empty() ? "" : ", ") + printable(doc.materialName(i));
        return s;
    };
    Document::LayerOrder order = doc.layerOrder();
    std::fprintf(out, "\nlayer order (drawn first to last):\n");
    for (const auto& [priority, materials] : order.deferred)
        std::fprintf(out, "  deferred layer %u: %s\n", unsigned(priority), names(materials).c_str());
    std::fprintf(out, "  forward: %s\n",
                 order.forward.empty() ? "(none)" : names(order.forward).c_str());
    std::fprintf(out, "\ntextures (%zu):\n", scene.textures.size());
    for (size_t t = 0; t < scene.textures.size(); ++t) {
        const pnb::TextureDesc& d = scene.textures[t];
        std::fprintf(out, "  %zu '%s' %ux%u %s %s, %u mips\n", t,
                     printable(scene.str(d.name)).c_str(), d.width, d.height, formatName(d.format),
                     d.colorSpace == pnb::ColorSpace::Srgb ? "srgb" : "linear", d.mipCount);
    }
}

void listJson(const Document& doc, std::FILE* out) {
    const pnb::Scene& scene = doc.scene();
    std::string j = "{\n  \"file\": " + jsonString(doc.path()) + ",\n  \"materials\": [";
    for (uint32_t i = 0; i < doc.materialCount(); ++i) {
        const pnb::Material& m = scene.materials[i];
        j += std::string(i ? "," : "") + "\n    {\"index\": " + std::to_string(i) +
             ", \"name\": " + jsonString(doc.materialName(i)) + ", \"program\": ";
        if (m.program == pnb::kNone) {
            j += "null";
        } else {
            const pnb::Program& p = scene.programs[m.program];
            j += "{\"index\": " + std::to_string(m.program) +
                 ", \"name\": " + jsonString(scene.str(p.name)) + ", \"defines\": [";
            for (size_t k = 0; k < p.defines.size(); ++k)
                j += (k ? ", " : "") + jsonString(scene.str(p.defines[k]));
            j += "]}";
        }
        j += ",\n     \"fields\": {";
        bool first = true;
        for (const pnb::MaterialField& f : pnb::materialFields()) {
            std::string v = pnb::getMaterialField(m, f.name), value;
            switch (f.type) {
            case pnb::FieldType::Float:
            case pnb::FieldType::Integer: value = jsonNumbers(v, false); break;
            case pnb::FieldType::Color3:
            case pnb::FieldType::Color4: value = jsonNumbers(v, true); break;
            case pnb::FieldType::Bool: value = v; break;
            case pnb::FieldType::Choice: value = jsonString(v); break;
            case pnb::FieldType::TextureRef: value = v == "none" ? "null" : v; break;
            }
            j += std::string(first ? "" : ", ") + "\"" + f.name + "\": " + value;
            first = false;
        }
        j += "}}";
    }
    j += "\n  ],\n  \"layers\": {\"deferred\": [";
    Document::LayerOrder order = doc.layerOrder();
    auto indices = [](const std::vector<uint32_t>& list) {
        std::string s = "[";
        for (size_t k = 0; k < list.size(); ++k) s += (k ? ", " : "") + std::to_string(list[k]);
        return s + "]";
    };
    for (size_t k = 0; k < order.deferred.size(); ++k)
        j += std::string(k ? ", " : "") + "{\"priority\": " +
             std::to_string(order.deferred[k].first) +
             ", \"materials\": " + indices(order.deferred[k].second) + "}";
    j += "], \"forward\": " + indices(order.forward) + "},\n  \"textures\": [";
    for (size_t t = 0; t < scene.textures.size(); ++t) {
        const pnb::TextureDesc& d = scene.textures[t];
        j += std::string(t ? "," : "") + "\n    {\"index\": " + std::to_string(t) +
             ", \"name\": " + jsonString(scene.str(d.name)) +
             ", \"width\": " + std::to_string(d.width) + ", \"height\": " +
             std::to_string(d.height) + ", \"format\": \"" + formatName(d.format) +
             "\", \"color_space\": \"" +
             (d.colorSpace == pnb::ColorSpace::Srgb ? "srgb" : "linear") +
             "\", \"mips\": " + std::to_string(d.mipCount) + "}";
    }
    j += scene.textures.empty() ? "]\n}\n" : "\n  ]\n}\n";
    std::fputs(j.c_str(), out);
}

// [SECTION] batch mode

// Two names of one existing file (a hard link, "./x" and "x", a symlink).
bool sameFile(const std::string& a, const std::string& b) {
    auto sa = pnb::stampOf(a), sb = pnb::stampOf(b);
    return sa && sb && sa->exists && sb->exists && sa->device == sb->device &&
           sa->inode == sb->inode;
}

// The edits one --set expression stands for; errors list the valid fields or material names.
pnb::Result<std::vector<Document::FieldEdit>> expand(const Document& doc,
                                                     const pnb::editor::SetExpression& e) {
    bool known = false;
    std::string fields;
    for (const pnb::MaterialField& f : pnb::materialFields()) {
        known |= e.field == f.name;
        fields += std::string(fields.empty() ? "" : ", ") + f.name;
    }
    if (!known)
        return pnb::makeError(pnb::FormatError::BadReference, 0,
                              "unknown material field '%s'; fields: %s", e.field.c_str(),
                              fields.c_str());
    std::vector<Document::FieldEdit> edits;
    std::string names;
    for (uint32_t i = 0; i < doc.materialCount(); ++i) {
        names += (names.empty() ? "" : ", ") + printable(doc.materialName(i));
        if (pnb::globMatch(e.pattern, doc.materialName(i))) edits.push_back({i, e.field, e.value});
    }
    if (edits.empty())
        return pnb::makeError(pnb::FormatError::BadReference, 0,
                              "no material matches '%s'; materials: %s",
                              printable(e.pattern).c_str(), names.empty() ? "(none)" : names.c_str());
    return edits;
}

int runBatch(const Settings& s) {
    std::FILE* info = s.json ? stderr : stdout; // keep stdout pure JSON
    // An edit in place holds the file's lock from this read to its rename: a concurrent edit
    // waits and then reads this one's result (pnb/file_lock.h). Writing elsewhere replaces
    // nothing this run read, so the input is not locked (and no run holds two locks).
    pnb::editor::DocumentOpenOptions open;
    open.lock.timeoutSeconds = s.lockTimeout;
    open.lock.onWait = [&s] {
        if (!s.quiet)
            std::fprintf(stderr, "waiting: another program is saving %s\n",
                         printable(s.output.empty() ? s.input : s.output).c_str());
    };
    const bool edited = !s.imports.empty() || !s.sets.empty();
    // -o may name the scene itself (an edit in place), never an image it imports.
    std::vector<pnb::RoleFile> images;
    for (const Import& i : s.imports) images.push_back({i.image, "the image imported as " + i.name});
    const pnb::RoleFile outputs[] = {{s.output, "the output (-o)"}};
    if (pnb::Status st = pnb::checkOutputs(images, outputs); !pnb::isOk(st))
        return usageError(st.message);
    if (pnb::Status st = pnb::checkInputs(images); !pnb::isOk(st)) return inputError(st);
    open.holdLock = edited && (s.output.empty() || sameFile(s.output, s.input));
    auto opened = Document::open(s.input, open);
    if (!opened) return inputError(opened.error());
    Document& doc = **opened;

    for (const Import& i : s.imports) {
        auto index = doc.importTexture(i.image, i.srgb, i.name, s.maxMemory);
        if (!index) return inputError(index.error());
        if (!s.quiet)
            std::fprintf(info, "imported '%s' as texture %u '%s' (%s)\n",
                         printable(i.image).c_str(), *index, printable(i.name).c_str(),
                         i.srgb ? "srgb" : "linear");
    }
    std::vector<Document::FieldEdit> edits;
    std::vector<std::string> summaries;
    for (const std::string& text : s.sets) {
        auto e = pnb::editor::parseSetExpression(text);
        if (!e) return usageError("--set: " + e.error().message);
        auto expanded = expand(doc, *e);
        if (!expanded) return inputError(expanded.error());
        summaries.push_back(e->field + " = " + e->value + " on " +
                            std::to_string(expanded->size()) + " material" +
                            (expanded->size() == 1 ? "" : "s") + " matching '" + e->pattern + "'");
        edits.insert(edits.end(), expanded->begin(), expanded->end());
    }
    if (!edits.empty())
        if (pnb::Status st = doc.apply(edits); !pnb::isOk(st)) return inputError(st);
    if (!s.quiet)
        for (const std::string& line : summaries)
            std::fprintf(info, "set %s\n", printable(line).c_str());
    // An edit the player cannot show is still applied (it may matter once the scene changes),
    // but never silently: one note per field and reason, with how many materials it concerns.
    std::map<std::pair<std::string, std::string>, size_t> noEffect;
    for (const Document::FieldEdit& e : s.quiet ? std::vector<Document::FieldEdit>{} : edits)
        if (std::string why = doc.noEffectReason(e.material, e.field); !why.empty())
            ++noEffect[{e.field, why}];
    for (const auto& [what, count] : noEffect)
        std::fprintf(stderr, "note: %s has no effect on %zu material%s: %s\n", what.first.c_str(),
                     count, count == 1 ? "" : "s", what.second.c_str());

    if (!s.output.empty() || (edited && doc.dirty())) {
        auto saved = doc.save(s.output);
        if (!saved) {
            std::fprintf(stderr, "Error: %s\n", saved.error().message.c_str());
            return isBusy(saved.error()) ? kExitBusy : kExitOutput;
        }
        if (!s.quiet)
            std::fprintf(info,
                         "saved %s: %llu bytes in %.3f s (%u chunks copied, %u rewritten, %u "
                         "added)\n",
                         printable(doc.path()).c_str(), (unsigned long long)saved->bytesWritten,
                         saved->seconds, saved->chunksCopied, saved->chunksRewritten,
                         saved->chunksAdded);
    } else if (edited && !s.quiet) {
        std::fprintf(info, "no change: %s not rewritten\n", printable(doc.path()).c_str());
    }
    if (s.list) (s.json ? listJson : listText)(doc, stdout);
    return kExitOk;
}

} // namespace

int main(int argc, char** argv) {
    // A scripted window session (--ui-*: the GUI smoke test) goes to the window code.
    for (int i = 1; i < argc; ++i)
        if (std::string_view(argv[i]).rfind("--ui-", 0) == 0) return pnb::editor::runGui(argc, argv);
    Settings s;
    bool help = false;
    const std::vector<pnb::cli::Option> table = options(s, help);
    auto scene = [&s](const char* arg) {
        if (!s.input.empty())
            return pnb::cli::Verdict::error("more than one scene ('" + s.input + "' and '" + arg + "')");
        if (!*arg) return pnb::cli::Verdict::error("empty file name");
        s.input = arg;
        return pnb::cli::Verdict(true);
    };
    if (auto e = pnb::cli::parse(table, scene, argc, argv)) {
        using Kind = pnb::cli::ParseError::Kind;
        switch (e->kind) {
        case Kind::UnknownOption: return usageError("unknown option '" + e->option + "'");
        case Kind::MissingValue: return usageError(e->option + " needs an argument " + e->valueName);
        case Kind::BadValue:
            return usageError(e->option + ": malformed argument '" + e->value + "', expected " + e->valueName);
        default: return usageError(pnb::cli::describe(*e));
        }
    }
    if (help) {
        printHelp(stdout, table);
        return kExitOk;
    }
    if (!s.batch()) {
        if (s.json) return usageError("--json needs --list");
        return pnb::editor::runGui(argc, argv);
    }
    if (s.json && !s.list) return usageError("--json needs --list");
    if (s.input.empty()) return usageError("no scene: pnb-edit SCENE.pnb ...");
    return runBatch(s);
}

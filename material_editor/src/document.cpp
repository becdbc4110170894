// Document: open, edits as immutable states, undo/redo, layer order. Program planning is in
// program_plan.cpp, texture import in texture_import.cpp, saving in document_save.cpp.

#include <algorithm>
#include <charconv>
#include <map>

#include "document_impl.h"
#include "pnb/material_fields.h"

namespace pnb::editor {

using detail::State;

namespace detail {

bool sameExceptProgram(Material a, Material b) {
    a.program = b.program = kNone;
    return encodeChunk(a) == encodeChunk(b);
}

} // namespace detail

namespace {

bool sameMaterials(const std::vector<Material>& a, const std::vector<Material>& b) {
    if (a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); ++i)
        if (encodeChunk(a[i]) != encodeChunk(b[i])) return false;
    return true;
}

const MaterialField* findField(std::string_view name) {
    for (const MaterialField& f : materialFields())
        if (name == f.name) return &f;
    return nullptr;
}

bool isIndex(std::string_view s) {
    unsigned v = 0;
    auto r = std::from_chars(s.data(), s.data() + s.size(), v);
    return !s.empty() && r.ec == std::errc() && r.ptr == s.data() + s.size();
}

} // namespace

// [SECTION] Impl: baseline and state

Status Document::Impl::load(const std::string& file) {
    // The stamp must describe the bytes read: taken before and after, and the read repeated
    // when another program replaced the file in between.
    std::optional<Container> opened;
    std::optional<Scene> decoded;
    for (int attempt = 1;; ++attempt) {
        auto before = stampOf(file);
        if (!before) return before.error();
        auto c = Container::open(file); // checksums verified as readScene loads each chunk
        if (!c) return c.error();
        auto sc = readScene(*c);
        if (!sc) {
            Error e = sc.error();
            e.message = file + ": " + e.message;
            return e;
        }
        auto after = stampOf(file);
        if (!after) return after.error();
        if (*before == *after) {
            stamp = *after;
            opened = std::move(*c);
            decoded = std::move(*sc);
            break;
        }
        if (attempt == 5)
            return makeError(FormatError::ChangedOnDisk, 0,
                             "'%s' changed on disk %d times while it was being read",
                             file.c_str(), attempt);
    }
    path = file;
    scene = std::move(*decoded);
    container = std::move(*opened); // the mapping moves with it; scene views stay valid

    base = {};
    base.strings = scene.strings.strings.size();
    base.shaders = scene.shaders.size();
    base.programs = scene.programs.size();
    base.textures = scene.textures.size();
    base.mips = scene.textureMips.size();
    base.materials = scene.materials;
    for (const Material& m : scene.materials) base.materialNames.emplace_back(scene.str(m.name));
    for (const TextureDesc& t : scene.textures) base.textureNames.emplace_back(scene.str(t.name));
    base.meshesOf.assign(scene.materials.size(), {});
    for (uint32_t m = 0; m < scene.meshes.size(); ++m)
        for (const Submesh& sm : scene.meshes[m].submeshes)
            if (sm.material < scene.materials.size()) {
                auto& list = base.meshesOf[sm.material];
                if (list.empty() || list.back() != m) list.push_back(m);
            }
    // Vertex colours are the one feature the material's fields do not show: the converter
    // enables them when the source primitive had colours. Keep the file's choice; without a
    // program to ask, a mesh with a colour stream drawing the material decides.
    base.vertexColor.assign(scene.materials.size(), false);
    for (size_t i = 0; i < scene.materials.size(); ++i) {
        const Material& m = scene.materials[i];
        if (m.program != kNone) {
            for (StringRef d : scene.programs[m.program].defines)
                if (scene.str(d) == "HAS_VERTEX_COLOR") base.vertexColor[i] = true;
            continue;
        }
        for (uint32_t mesh : base.meshesOf[i])
            for (const VertexStream& s : scene.meshes[mesh].streams)
                if (s.semantic == VertexSemantic::Color0) base.vertexColor[i] = true;
    }

    pool.clear();
    stringIndex.clear();
    for (size_t i = 0; i < scene.strings.strings.size(); ++i)
        stringIndex.emplace(std::string(scene.strings.strings[i]), StringRef(i));
    base.sceneLevelBefore = sceneLevelVariants(base.materials);
    return {};
}

StringRef Document::Impl::intern(std::string_view s) {
    auto it = stringIndex.find(std::string(s));
    if (it != stringIndex.end()) return it->second;
    const std::string& kept = pool.emplace_back(s);
    StringRef ref = StringRef(scene.strings.strings.size());
    scene.strings.strings.push_back(kept);
    stringIndex.emplace(kept, ref);
    return ref;
}

void Document::Impl::materialize() {
    scene.materials = current.materials;
    scene.shaders.resize(base.shaders);
    for (const std::string& file : current.addedShaders) {
        const detail::ResolvedStage& st = stages.at(file);
        scene.shaders.push_back(ShaderSource{
            intern(file), st.stage,
            Blob(reinterpret_cast<const std::byte*>(st.text.data()), st.text.size())});
    }
    scene.programs.resize(base.programs);
    for (const detail::AddedProgram& a : current.addedPrograms) {
        Program p;
        p.name = intern(a.variant.name);
        p.shaders = a.shaders;
        for (const std::string& d : a.variant.defines) p.defines.push_back(intern(d));
        scene.programs.push_back(std::move(p));
    }
    scene.textures.resize(base.textures);
    scene.textureMips.resize(base.mips);
    for (size_t k = 0; k < current.imported.size(); ++k) {
        const detail::ImportedTexture& t = *current.imported[k];
        TextureDesc d = t.desc;
        d.name = intern(t.name);
        scene.textures.push_back(d);
        uint32_t index = uint32_t(base.textures + k);
        for (uint32_t level = 0; level < t.levels.size(); ++level)
            scene.textureMips.push_back(TextureMip{index, level, std::max(1u, d.width >> level),
                                                   std::max(1u, d.height >> level),
                                                   Blob(t.levels[level])});
    }
}

void Document::Impl::updateDirty() {
    isDirty = current.imported != savedImports || !sameMaterials(current.materials, savedMaterials);
}

std::string Document::Impl::materialLabel(uint32_t index) const {
    std::string_view name = scene.str(current.materials[index].name);
    return name.empty() ? "#" + std::to_string(index) : "'" + std::string(name) + "'";
}

std::string_view Document::Impl::textureName(uint32_t index, const State& state) const {
    return index < base.textures ? scene.str(scene.textures[index].name)
                                 : std::string_view(state.imported[index - base.textures]->name);
}

std::string Document::Impl::textureList(size_t count, const State& state) const {
    std::string list;
    for (uint32_t i = 0; i < count; ++i)
        list += (list.empty() ? "" : ", ") + std::to_string(i) + " '" +
                std::string(textureName(i, state)) + "'";
    return list.empty() ? "none (the scene has no textures)" : list + ", or none";
}

Result<State> Document::Impl::makeState(
    std::vector<Material> materials,
    std::vector<std::shared_ptr<const detail::ImportedTexture>> imported) {
    State next;
    next.imported = std::move(imported);
    const size_t textureCount = base.textures + next.imported.size();
    for (uint32_t i = 0; i < materials.size(); ++i)
        for (size_t slot = 0; slot < materials[i].textures.size(); ++slot) {
            uint32_t t = materials[i].textures[slot].texture;
            if (t == kNone || t < textureCount) continue;
            static constexpr const char* kSlotFields[] = {
                "base_color_texture", "metallic_roughness_texture", "normal_texture",
                "occlusion_texture", "emissive_texture"};
            return makeError(FormatError::BadReference, 0,
                             "material %s: %s = %u, but there is no texture %u; textures: %s",
                             materialLabel(i).c_str(), kSlotFields[slot], t, t,
                             textureList(textureCount, next).c_str());
        }
    if (Status s = checkStreams(materials); !isOk(s)) return s;
    auto plan = planPrograms(materials);
    if (!plan) return plan.error();
    for (size_t i = 0; i < materials.size(); ++i) materials[i].program = plan->materialProgram[i];
    next.materials = std::move(materials);
    next.addedPrograms = std::move(plan->addedPrograms);
    next.addedShaders = std::move(plan->addedShaders);
    return next;
}

void Document::Impl::pushState(State next, bool merge) {
    if (!(merge && lastWasEdit && !undoStack.empty())) undoStack.push_back(std::move(current));
    current = std::move(next);
    redoStack.clear();
    lastWasEdit = true;
    materialize();
    updateDirty();
}

// [SECTION] Document

Document::Document() : mImpl(std::make_unique<Impl>()) {}
Document::~Document() = default;

Result<std::unique_ptr<Document>> Document::open(const std::string& path,
                                                  const OpenOptions& options) {
    std::unique_ptr<Document> doc(new Document());
    Impl& d = *doc->mImpl;
    d.lockOptions = options.lock;
    if (options.holdLock) {
        auto lock = FileLock::acquire(path, options.lock);
        if (!lock) return lock.error();
        d.heldLock = std::move(*lock);
    }
    if (Status s = d.load(path); !isOk(s)) return s;
    d.current.materials = d.scene.materials;
    d.savedMaterials = d.current.materials;
    return doc;
}

const std::string& Document::path() const { return mImpl->path; }
const FileStamp& Document::stamp() const { return mImpl->stamp; }
const Scene& Document::scene() const { return mImpl->scene; }
size_t Document::materialCount() const { return mImpl->current.materials.size(); }

std::string_view Document::materialName(uint32_t index) const {
    return mImpl->scene.str(mImpl->current.materials.at(index).name);
}

Status Document::setField(uint32_t index, std::string_view field, std::string_view value,
                          bool mergeWithPrevious) {
    return mImpl->applyEdits({{index, std::string(field), std::string(value)}}, mergeWithPrevious);
}

std::string Document::noEffectReason(uint32_t index, std::string_view field) const {
    if (index >= mImpl->current.materials.size()) return {};
    const Material& m = mImpl->current.materials[index];
    const bool shadowField = field == "receives_shadows" || field == "casts_shadows";
    if (shadowField && !mImpl->sceneNeeds(mImpl->current.materials).shadows) {
        bool shadowLight = false;
        for (const Light& l : mImpl->scene.lights.lights) shadowLight |= l.castsShadows;
        return shadowLight ? "no material casts shadows, so the scene has no shadow pass"
                           : "the scene has no shadow-casting light";
    }
    if (field == "alpha_cutoff" && m.alphaMode != AlphaMode::Mask)
        return "alpha_cutoff applies to alpha_mode mask only";
    return {};
}

Status Document::apply(const std::vector<FieldEdit>& edits) {
    return mImpl->applyEdits(edits, false);
}

Status Document::Impl::applyEdits(const std::vector<FieldEdit>& edits, bool merge) {
    std::vector<Material> edited = current.materials;
    const size_t textureCount = base.textures + current.imported.size();
    for (const FieldEdit& e : edits) {
        if (e.material >= edited.size()) {
            if (edited.empty())
                return makeError(FormatError::BadReference, 0,
                                 "material %u does not exist: the scene has no materials",
                                 e.material);
            return makeError(FormatError::BadReference, 0,
                             "material %u does not exist; the scene has %zu (0..%zu)",
                             e.material, edited.size(), edited.size() - 1);
        }
        std::string value = e.value;
        const MaterialField* f = findField(e.field);
        if (f && f->type == FieldType::TextureRef && value != "none" && !isIndex(value)) {
            // A texture by name.
            std::vector<uint32_t> found;
            for (uint32_t t = 0; t < textureCount; ++t)
                if (textureName(t, current) == value) found.push_back(t);
            if (found.size() != 1)
                return makeError(FormatError::BadReference, 0,
                                 "material %s: %s = '%s': %s; textures: %s",
                                 materialLabel(e.material).c_str(), f->name, value.c_str(),
                                 found.empty() ? "no texture has this name"
                                               : "several textures have this name (use an index)",
                                 textureList(textureCount, current).c_str());
            value = std::to_string(found[0]);
        }
        if (Status s = setMaterialField(edited[e.material], e.field, value); !isOk(s)) {
            s.message = "material " + materialLabel(e.material) + ": " + s.message;
            return s;
        }
    }
    // Unchanged content is no step (and does not make the document dirty).
    bool changed = false;
    for (size_t i = 0; i < edited.size() && !changed; ++i)
        changed = !detail::sameExceptProgram(edited[i], current.materials[i]);
    if (!changed) return {};
    auto next = makeState(std::move(edited), current.imported);
    if (!next) return next.error();
    pushState(std::move(*next), merge);
    return {};
}

bool Document::canUndo() const { return !mImpl->undoStack.empty(); }
bool Document::canRedo() const { return !mImpl->redoStack.empty(); }

void Document::undo() {
    Impl& d = *mImpl;
    if (d.undoStack.empty()) return;
    d.redoStack.push_back(std::move(d.current));
    d.current = std::move(d.undoStack.back());
    d.undoStack.pop_back();
    d.lastWasEdit = false;
    d.materialize();
    d.updateDirty();
}

void Document::redo() {
    Impl& d = *mImpl;
    if (d.redoStack.empty()) return;
    d.undoStack.push_back(std::move(d.current));
    d.current = std::move(d.redoStack.back());
    d.redoStack.pop_back();
    d.lastWasEdit = false;
    d.materialize();
    d.updateDirty();
}

bool Document::dirty() const { return mImpl->isDirty; }

Document::LayerOrder Document::layerOrder() const {
    LayerOrder order;
    std::map<uint16_t, std::vector<uint32_t>> layers;
    const auto& materials = mImpl->current.materials;
    for (uint32_t i = 0; i < materials.size(); ++i) {
        if (materials[i].shadingPath == ShadingPath::Deferred)
            layers[materials[i].layerPriority].push_back(i);
        else
            order.forward.push_back(i);
    }
    order.deferred.assign(layers.begin(), layers.end());
    return order;
}

Result<SaveStats> Document::save(const std::string& path) { return mImpl->save(path); }

Result<Document::DiskChange> Document::compareWithDisk() const {
    auto c = mImpl->compareWithDisk();
    if (!c) return c.error();
    return std::move(c->change);
}

Status Document::reload(Reload mode) { return mImpl->reload(mode); }

} // namespace pnb::editor

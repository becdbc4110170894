// Saving: the opened file's chunks in their order, each either copied as stored
// (Writer::copyChunk: no decode, no re-compression) or, for STRS and edited MATL, re-encoded;
// new SHDR/PROG/TEXR chunks after the last of their kind and new TMIP levels merged into the
// smallest-level-first order (FORMAT.md §4.1). The Writer makes it atomic (temporary, fsync,
// rename). Afterwards the written file is the document's baseline.

#include <algorithm>
#include <chrono>
#include <unordered_map>

#include "document_impl.h"
#include "pnb/writer.h"

namespace pnb::editor {

namespace {

Document::SaveProbe gSaveProbe = nullptr;


double secondsSince(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

} // namespace

void Document::setSaveProbeForTesting(SaveProbe probe) { gSaveProbe = probe; }

Result<SaveStats> Document::Impl::save(const std::string& target) {
    const auto start = std::chrono::steady_clock::now();
    const std::string out = target.empty() ? path : target;
    const Container& source = *container;
    SaveStats stats;

    // [SECTION] what the state adds, with its new strings numbered after the file's
    std::unordered_map<StringRef, StringRef> remap;
    std::vector<std::string_view> newStrings;
    auto use = [&](StringRef r) {
        if (r == kNone || r < base.strings) return r;
        auto [it, added] = remap.emplace(r, StringRef(base.strings + newStrings.size()));
        if (added) newStrings.push_back(scene.strings.strings[r]);
        return it->second;
    };
    std::vector<ShaderSource> newShaders(scene.shaders.begin() + long(base.shaders),
                                         scene.shaders.end());
    for (ShaderSource& s : newShaders) s.name = use(s.name);
    std::vector<Program> newPrograms(scene.programs.begin() + long(base.programs),
                                     scene.programs.end());
    for (Program& p : newPrograms) {
        p.name = use(p.name);
        for (StringRef& d : p.defines) d = use(d);
    }
    std::vector<TextureDesc> newTextures(scene.textures.begin() + long(base.textures),
                                         scene.textures.end());
    for (TextureDesc& t : newTextures) t.name = use(t.name);
    // Smallest level first; stable, so equal levels stay in texture order (as writeScene).
    std::vector<const TextureMip*> newMips;
    for (size_t i = base.mips; i < scene.textureMips.size(); ++i)
        newMips.push_back(&scene.textureMips[i]);
    std::stable_sort(newMips.begin(), newMips.end(),
                     [](const TextureMip* a, const TextureMip* b) { return a->level > b->level; });

    // Chunks the writer creates follow the file's conventions: checksums if its string table
    // has one; new texels compressed if its bulk chunks are.
    WriteOptions options;
    Compression bulk = Compression::None;
    for (const ChunkInfo& c : source.chunks()) {
        if (c.header.tag == tags::kStrings) options.checksums = c.header.hasChecksum();
        if (c.header.tag == tags::kTextureMip || c.header.tag == tags::kMesh)
            bulk = c.header.compression();
    }
    if (Status s = guardSave(out, options); !isOk(s)) return s;
    auto writer = Writer::create(out, options);
    if (!writer) return writer.error();
    Writer& w = *writer;

    uint32_t written = 0;
    auto done = [&](Status s, uint32_t& counter) {
        if (!isOk(s)) return s;
        ++counter;
        ++written;
        if (gSaveProbe) gSaveProbe("chunk", written);
        return s;
    };
    // New chunks of a kind go after the file's last chunk of that kind: before the first chunk
    // of a later kind (or at the end).
    struct Group {
        int rank;
        bool flushed = false;
    };
    Group groups[] = {{streamOrderRank(tags::kShader)}, {streamOrderRank(tags::kProgram)},
                      {streamOrderRank(tags::kTexture)}};
    auto flushBelow = [&](int rank) -> Status {
        for (Group& g : groups) {
            if (g.flushed || g.rank >= rank) continue;
            g.flushed = true;
            Status s;
            if (g.rank == streamOrderRank(tags::kShader))
                for (const ShaderSource& sh : newShaders)
                    if (s = done(writeChunk(w, sh), stats.chunksAdded); !isOk(s)) return s;
            if (g.rank == streamOrderRank(tags::kProgram))
                for (const Program& p : newPrograms)
                    if (s = done(writeChunk(w, p), stats.chunksAdded); !isOk(s)) return s;
            if (g.rank == streamOrderRank(tags::kTexture))
                for (const TextureDesc& t : newTextures)
                    if (s = done(writeChunk(w, t), stats.chunksAdded); !isOk(s)) return s;
        }
        return {};
    };
    size_t nextMip = 0;
    auto mipsAbove = [&](uint32_t level) -> Status { // new levels > level, i.e. smaller ones
        for (; nextMip < newMips.size() && newMips[nextMip]->level > level; ++nextMip)
            if (Status s = done(writeChunk(w, *newMips[nextMip], bulk), stats.chunksAdded);
                !isOk(s))
                return s;
        return {};
    };

    // A chunk of a newer version than this build knows carries appended fields it cannot
    // re-encode (FORMAT.md 3.5): rewriting it would silently drop them, so refuse instead.
    auto refuseNewer = [](const ChunkInfo& c, uint16_t known, const char* what) -> Status {
        if (c.header.version <= known) return {};
        return makeError(FormatError::UnsupportedChunkVersion, c.headerOffset,
                         "%s is chunk version %u, newer than this editor's %u: saving the edit "
                         "would drop fields this editor does not know; update Penumbra",
                         what, c.header.version, known);
    };
    uint32_t materialIndex = 0, mipIndex = 0;
    for (const ChunkInfo& c : source.chunks()) {
        const Tag tag = c.header.tag;
        const int rank = streamOrderRank(tag);
        if (rank >= 0)
            if (Status s = flushBelow(rank); !isOk(s)) return s;
        Status s;
        if (tag == tags::kStrings && !newStrings.empty()) {
            if (s = refuseNewer(c, ChunkTraits<StringTable>::version, "the string table");
                !isOk(s))
                return s;
            StringTable table;
            table.strings.assign(scene.strings.strings.begin(),
                                 scene.strings.strings.begin() + long(base.strings));
            table.strings.insert(table.strings.end(), newStrings.begin(), newStrings.end());
            s = done(writeChunk(w, table, c.header.compression()), stats.chunksRewritten);
        } else if (tag == tags::kMaterial &&
                   encodeChunk(current.materials[materialIndex]) !=
                       encodeChunk(base.materials[materialIndex])) {
            const std::string what = "material " + std::to_string(materialIndex);
            if (s = refuseNewer(c, ChunkTraits<Material>::version, what.c_str()); !isOk(s))
                return s;
            s = done(writeChunk(w, current.materials[materialIndex], c.header.compression()),
                     stats.chunksRewritten);
        } else {
            if (tag == tags::kTextureMip)
                if (s = mipsAbove(scene.textureMips[mipIndex].level); !isOk(s)) return s;
            s = done(w.copyChunk(source, c), stats.chunksCopied);
        }
        if (!isOk(s)) return s;
        materialIndex += tag == tags::kMaterial;
        mipIndex += tag == tags::kTextureMip;
    }
    if (Status s = flushBelow(1 << 30); !isOk(s)) return s;
    for (; nextMip < newMips.size(); ++nextMip) // levels no file TMIP came after (e.g. all)
        if (Status s = done(writeChunk(w, *newMips[nextMip], bulk), stats.chunksAdded); !isOk(s))
            return s;
    if (gSaveProbe) gSaveProbe("commit", written);
    if (Status s = w.commit(); !isOk(s)) return s;
    heldLock.reset(); // it locked the file the save replaced
    stats.bytesWritten = w.size();
    stats.seconds = secondsSince(start);

    const auto reload = std::chrono::steady_clock::now();
    if (Status s = rebase(out); !isOk(s)) {
        s.message = "saved '" + out + "', but reading it back failed: " + s.message;
        return s;
    }
    stats.reloadSeconds = secondsSince(reload);
    return stats;
}

Status Document::Impl::rebase(const std::string& file) {
    const size_t oldTextures = base.textures;
    detail::State saved = current;
    if (Status s = load(file); !isOk(s)) return s;

    // The file now holds the saved state: it is the current state, clean.
    current = detail::State{scene.materials, {}, {}, {}};
    savedMaterials = current.materials;
    savedImports.clear();

    // Re-express an older or newer state against the new file: imports the file now holds
    // become file textures, the others stay imports; programs are planned anew.
    auto rebaseState = [&](const detail::State& st) -> Result<detail::State> {
        std::vector<std::shared_ptr<const detail::ImportedTexture>> still;
        for (const auto& p : st.imported)
            if (std::find(saved.imported.begin(), saved.imported.end(), p) == saved.imported.end())
                still.push_back(p);
        std::vector<Material> materials = st.materials;
        for (Material& m : materials)
            for (TextureSlot& slot : m.textures) {
                if (slot.texture == kNone || slot.texture < oldTextures) continue;
                const auto& p = st.imported[slot.texture - oldTextures];
                auto inFile = std::find(saved.imported.begin(), saved.imported.end(), p);
                slot.texture =
                    inFile != saved.imported.end()
                        ? uint32_t(oldTextures + size_t(inFile - saved.imported.begin()))
                        : uint32_t(base.textures +
                                   size_t(std::find(still.begin(), still.end(), p) - still.begin()));
            }
        return makeState(std::move(materials), std::move(still));
    };
    bool ok = true;
    for (auto* stack : {&undoStack, &redoStack})
        for (detail::State& st : *stack) {
            if (!ok) break;
            auto r = rebaseState(st);
            if (r) st = std::move(*r);
            else ok = false;
        }
    if (!ok) { // cannot happen for states that were valid; never keep a wrong history
        undoStack.clear();
        redoStack.clear();
    }
    lastWasEdit = false;
    materialize();
    updateDirty();
    return {};
}

} // namespace pnb::editor

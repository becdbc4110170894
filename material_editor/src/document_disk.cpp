// The document against the file on disk: what another program changed since the document read
// it (compareWithDisk), the save's guard against it (guardSave: the lock and the
// compare-before-rename), and re-reading the file with this document's edits on top (reload).

#include <map>

#include "document_impl.h"
#include "pnb/material_fields.h"

namespace pnb::editor {

namespace {

constexpr size_t kListed = 6; // entries of a list that a message shows

std::string quoted(std::string_view s) { return "'" + std::string(s) + "'"; }

std::string joined(const std::vector<std::string>& items) {
    std::string out;
    for (size_t i = 0; i < items.size() && i < kListed; ++i) out += (i ? ", " : "") + items[i];
    if (items.size() > kListed) out += " and " + std::to_string(items.size() - kListed) + " more";
    return out;
}

// Material i of `a` to its counterpart in `b` (-1: none): by name where the name is unique in
// both files, else by index where the index holds the same name (duplicates, unnamed).
std::vector<int> matchMaterials(const std::vector<std::string_view>& a,
                                const std::vector<std::string_view>& b) {
    std::map<std::string_view, int> countA, countB, indexB;
    for (std::string_view n : a) ++countA[n];
    for (size_t j = 0; j < b.size(); ++j) ++countB[b[j]], indexB[b[j]] = int(j);
    std::vector<int> match(a.size(), -1);
    for (size_t i = 0; i < a.size(); ++i) {
        if (!a[i].empty() && countA[a[i]] == 1 && countB[a[i]] == 1) match[i] = indexB[a[i]];
        else if (i < b.size() && b[i] == a[i]) match[i] = int(i);
    }
    return match;
}

} // namespace

std::string Document::DiskChange::describe(const std::string& file) const {
    std::string s = quoted(file) + " changed on disk since it was read (then " + was.describe() +
                    "; now " + now.describe() + ")";
    if (!readable) return s + ": " + joined(theirs);
    s += theirs.empty() ? "; no material differs (another part of the file changed)"
                        : "; their changes: " + joined(theirs);
    if (!conflicts.empty()) s += "; conflicting with your edits: " + joined(conflicts);
    return s;
}

Result<Document::Impl::DiskComparison> Document::Impl::compareWithDisk() const {
    DiskComparison out;
    Document::DiskChange& change = out.change;
    change.was = stamp;
    auto now = stampOf(path);
    if (!now) return now.error();
    change.now = *now;

    // A field as text that means the same in both files: texture slots by texture name.
    auto text = [](const Material& m, const MaterialField& f, auto&& textureName) {
        std::string v = getMaterialField(m, f.name);
        if (f.type != FieldType::TextureRef || v == "none") return v;
        return "texture " + quoted(textureName(uint32_t(std::stoul(v))));
    };
    auto ours = [&](uint32_t t) -> std::string_view {
        return t < base.textures ? base.textureNames[t] : current.imported[t - base.textures]->name;
    };
    std::vector<std::pair<uint32_t, const MaterialField*>> edited; // (material, field) of mine
    for (uint32_t i = 0; i < current.materials.size(); ++i)
        for (const MaterialField& f : materialFields())
            if (text(current.materials[i], f, ours) != text(base.materials[i], f, ours))
                edited.emplace_back(i, &f);
    change.mine = uint32_t(edited.size());

    if (!now->exists) {
        change.readable = false;
        change.theirs.push_back("the file was removed");
        return out;
    }
    std::optional<Container> file; // keeps `other`'s views mapped
    std::optional<Scene> other;
    if (auto c = Container::open(path); !c) {
        change.theirs.push_back("it is no longer a readable container: " + c.error().describe());
    } else if (file = std::move(*c); auto sc = readScene(*file)) {
        other = std::move(*sc);
    } else {
        change.theirs.push_back("it is no longer a readable container: " + sc.error().describe());
    }
    if (!other) {
        change.readable = false;
        return out;
    }
    auto theirsName = [&](uint32_t t) {
        return t < other->textures.size() ? other->str(other->textures[t].name)
                                          : std::string_view("?");
    };
    std::vector<std::string_view> namesA, namesB;
    for (const std::string& name : base.materialNames) namesA.push_back(name);
    for (const Material& m : other->materials) namesB.push_back(other->str(m.name));
    const std::vector<int> match = matchMaterials(namesA, namesB);
    auto label = [&](uint32_t i) {
        return namesA[i].empty() ? "#" + std::to_string(i) : quoted(namesA[i]);
    };
    std::vector<bool> matched(namesB.size(), false);
    for (uint32_t i = 0; i < base.materials.size(); ++i) {
        if (match[i] < 0) {
            change.theirs.push_back("material " + label(i) + " is gone");
            continue;
        }
        matched[size_t(match[i])] = true;
        const Material& theirs = other->materials[size_t(match[i])];
        for (const MaterialField& f : materialFields()) {
            const std::string before = text(base.materials[i], f, ours),
                              after = text(theirs, f, theirsName);
            if (before != after)
                change.theirs.push_back(label(i) + "." + f.name + ": " + before + " -> " + after);
        }
    }
    for (size_t j = 0; j < namesB.size(); ++j)
        if (!matched[j])
            change.theirs.push_back("material " +
                                    (namesB[j].empty() ? "#" + std::to_string(j)
                                                       : quoted(namesB[j])) +
                                    " is new");

    // Mine against theirs, and the plan that applies mine to their file.
    for (auto [i, f] : edited) {
        const std::string was = text(base.materials[i], *f, ours),
                          mine = text(current.materials[i], *f, ours);
        if (match[i] < 0) {
            change.conflicts.push_back(label(i) + "." + f->name + ": you edited it, their file " +
                                       "no longer has this material");
            out.unmergeable = true;
            continue;
        }
        const uint32_t j = uint32_t(match[i]);
        const std::string theirs = text(other->materials[j], *f, theirsName);
        if (theirs != was && theirs != mine)
            change.conflicts.push_back(label(i) + "." + f->name + ": mine " + mine + ", theirs " +
                                       theirs);
        std::string value = getMaterialField(current.materials[i], f->name);
        if (f->type == FieldType::TextureRef && value != "none") {
            const uint32_t t = uint32_t(std::stoul(value));
            if (t >= base.textures) { // an import: it follows the new file's textures
                value = std::to_string(other->textures.size() + (t - base.textures));
            } else {
                std::vector<uint32_t> same;
                for (uint32_t k = 0; k < other->textures.size(); ++k)
                    if (theirsName(k) == ours(t)) same.push_back(k);
                if (same.size() != 1) {
                    change.conflicts.push_back(label(i) + "." + f->name + ": your texture " +
                                               quoted(ours(t)) + " is " +
                                               (same.empty() ? "not in" : "not unique in") +
                                               " their file");
                    out.unmergeable = true;
                    continue;
                }
                value = std::to_string(same[0]);
            }
        }
        out.plan.push_back({j, f->name, std::move(value)});
    }
    return out;
}

Status Document::Impl::unchangedOnDisk() const {
    auto now = stampOf(path);
    if (!now) return now.error();
    if (*now == stamp) return {};
    Document::DiskChange unread; // when the new file cannot even be compared
    unread.was = stamp;
    unread.now = *now;
    auto c = compareWithDisk();
    return Error{FormatError::ChangedOnDisk, 0,
                 (c ? c->change : unread).describe(path) +
                     ". Nothing was written: merge your edits into the file as it is now (the "
                     "window's Merge; pnb-edit --set again), or save to another path"};
}

Status Document::Impl::guardSave(const std::string& target, WriteOptions& options) {
    options.lock = lockOptions;
    bool inPlace = target == path;
    if (!inPlace)
        if (auto t = stampOf(target); t && t->exists)
            inPlace = t->device == stamp.device && t->inode == stamp.inode;
    if (!inPlace) {
        // Saving elsewhere copies the unedited chunks from the mapping: if another program
        // rewrote the file in place (same inode), those bytes are no longer the ones read.
        auto now = stampOf(path);
        if (now && now->exists && now->device == stamp.device && now->inode == stamp.inode &&
            !(*now == stamp))
            return Error{FormatError::ChangedOnDisk, 0,
                         "'" + path + "' was rewritten in place by another program (" +
                             now->describe() + ") while this document had it open, so the "
                             "unedited chunks it would copy changed: nothing was written. "
                             "Reload and merge your edits into the file as it is now"};
        return {};
    }
    // In place: the file must still be the one read (compare-before-rename), or another
    // program's save would be silently replaced. Checked now, which also spares writing a file
    // for nothing, and again under the lock just before the rename.
    if (Status s = unchangedOnDisk(); !isOk(s)) return s;
    options.heldLock = heldLock ? &*heldLock : nullptr;
    options.beforeReplace = [this] { return unchangedOnDisk(); };
    return {};
}

Status Document::Impl::reload(Document::Reload mode) {
    // Under the file's lock, so the file compared is the file read.
    std::optional<FileLock> lock;
    if (!heldLock) {
        auto l = FileLock::acquire(path, lockOptions);
        if (!l) return l.error();
        lock = std::move(*l);
    }
    DiskComparison cmp;
    if (mode != Document::Reload::Discard) {
        auto c = compareWithDisk();
        if (!c) return c.error();
        cmp = std::move(*c);
        const bool refused = !cmp.change.readable || cmp.unmergeable ||
                             (mode == Document::Reload::Merge && !cmp.change.conflicts.empty());
        if (refused)
            return Error{FormatError::ChangedOnDisk, 0,
                         "cannot merge your edits: " + cmp.change.describe(path)};
    }
    // Built aside and swapped in whole: on any error the document is unchanged.
    Impl fresh;
    fresh.lockOptions = lockOptions;
    fresh.stages = stages;
    fresh.validated = validated;
    if (Status s = fresh.load(path); !isOk(s)) return s;
    fresh.current.materials = fresh.scene.materials;
    fresh.savedMaterials = fresh.current.materials;
    if (mode != Document::Reload::Discard && !(fresh.stamp == cmp.change.now))
        return makeError(FormatError::ChangedOnDisk, 0,
                         "'%s' changed again while it was being merged; try again", path.c_str());
    if (mode != Document::Reload::Discard && (!cmp.plan.empty() || !current.imported.empty())) {
        std::vector<Material> materials = fresh.current.materials;
        for (const FieldEdit& e : cmp.plan)
            if (Status s = setMaterialField(materials[e.material], e.field, e.value); !isOk(s)) {
                s.message = "cannot merge your edit of " + fresh.materialLabel(e.material) +
                            "." + e.field + " into the file as it is now: " + s.message;
                return s;
            }
        auto next = fresh.makeState(std::move(materials), current.imported);
        if (!next) {
            Error e = next.error();
            e.message = "cannot merge your edits into the file as it is now: " + e.message;
            return e;
        }
        fresh.pushState(std::move(*next), false);
        fresh.lastWasEdit = false; // the merge is one step of its own
    }
    fresh.heldLock = std::move(heldLock);
    *this = std::move(fresh); // the same Impl (and Scene) object: scene() references stay valid
    return {};
}

} // namespace pnb::editor

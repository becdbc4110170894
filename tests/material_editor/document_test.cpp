// pnb::editor::Document: edits, undo/redo and dirty semantics, all-or-nothing batches, errors
// that list what is valid, program planning that matches the converter's, texture import.

#include <gtest/gtest.h>

#include "editor_test_util.h"
#include "pnb/material_fields.h"

namespace {

using namespace pnb;
using namespace pnb::editor;
using namespace pnb::editor::test;


std::string field(const Document& d, uint32_t material, const char* name) {
    return getMaterialField(d.scene().materials[material], name);
}

std::vector<std::vector<std::byte>> encodedMaterials(const Document& d) {
    std::vector<std::vector<std::byte>> out;
    for (const Material& m : d.scene().materials) out.push_back(encodeChunk(m));
    return out;
}

TEST(Document, OpenErrorsNameTheFile) {
    TempDir dir;
    auto missing = Document::open(dir.file("nope.pnb"));
    ASSERT_FALSE(missing.ok());
    EXPECT_NE(missing.error().message.find("nope.pnb"), std::string::npos)
        << missing.error().message;
    writeBytes(dir.file("junk.pnb"), std::vector<uint8_t>(300, 7));
    auto junk = Document::open(dir.file("junk.pnb"));
    ASSERT_FALSE(junk.ok());
    EXPECT_EQ(junk.error().code, FormatError::BadMagic);
    EXPECT_NE(junk.error().message.find("junk.pnb"), std::string::npos) << junk.error().message;
}

TEST(Document, UndoRedoAndDirty) {
    TempDir dir;
    auto doc = openDoc(copyScene(dir, "grazing-plane"));
    ASSERT_TRUE(doc);
    const uint32_t box = materialIndex(doc->scene(), "box");
    const std::string original = field(*doc, box, "roughness");
    EXPECT_FALSE(doc->dirty());
    EXPECT_FALSE(doc->canUndo());
    EXPECT_FALSE(doc->canRedo());

    ASSERT_TRUE(isOk(doc->setField(box, "roughness", "0.25")));
    EXPECT_EQ(field(*doc, box, "roughness"), "0.25");
    EXPECT_TRUE(doc->dirty());
    ASSERT_TRUE(isOk(doc->setField(box, "metallic", "1")));
    EXPECT_TRUE(doc->canUndo());

    doc->undo();
    EXPECT_EQ(field(*doc, box, "metallic"), "0");
    EXPECT_EQ(field(*doc, box, "roughness"), "0.25");
    EXPECT_TRUE(doc->dirty());
    EXPECT_TRUE(doc->canRedo());
    doc->undo();
    EXPECT_EQ(field(*doc, box, "roughness"), original);
    EXPECT_FALSE(doc->dirty()) << "back at the file's content";
    EXPECT_FALSE(doc->canUndo());
    doc->undo(); // nothing to undo: no-op
    EXPECT_EQ(field(*doc, box, "roughness"), original);

    doc->redo();
    doc->redo();
    EXPECT_EQ(field(*doc, box, "metallic"), "1");
    EXPECT_FALSE(doc->canRedo());
    doc->redo(); // no-op

    // A new edit after an undo drops the redo branch.
    doc->undo();
    ASSERT_TRUE(isOk(doc->setField(box, "emissive", "1,0,0")));
    EXPECT_FALSE(doc->canRedo());

    // Setting a value back by hand is clean again: dirty compares content, not history.
    TempDir other;
    auto fresh = openDoc(copyScene(other, "grazing-plane"));
    ASSERT_TRUE(isOk(fresh->setField(box, "roughness", "0.3")));
    ASSERT_TRUE(isOk(fresh->setField(box, "roughness", original)));
    EXPECT_FALSE(fresh->dirty());
    EXPECT_TRUE(fresh->canUndo());
    // An edit that changes nothing is no step.
    TempDir third;
    auto same = openDoc(copyScene(third, "grazing-plane"));
    ASSERT_TRUE(isOk(same->setField(box, "roughness", original)));
    EXPECT_FALSE(same->canUndo());
    EXPECT_FALSE(same->dirty());
}

TEST(Document, MergedEditsAreOneStep) {
    TempDir dir;
    auto doc = openDoc(copyScene(dir, "grazing-plane"));
    ASSERT_TRUE(doc);
    const uint32_t box = materialIndex(doc->scene(), "box");
    const std::string original = field(*doc, box, "roughness");
    // A slider drag: the first value is a step, the rest fold into it.
    ASSERT_TRUE(isOk(doc->setField(box, "roughness", "0.5", true)));
    ASSERT_TRUE(isOk(doc->setField(box, "roughness", "0.4", true)));
    ASSERT_TRUE(isOk(doc->setField(box, "roughness", "0.3", true)));
    doc->undo();
    EXPECT_EQ(field(*doc, box, "roughness"), original);
    EXPECT_FALSE(doc->canUndo());
    // Never merged into a state reached by undo: that would rewrite history.
    doc->redo();
    EXPECT_EQ(field(*doc, box, "roughness"), "0.300000012");
    ASSERT_TRUE(isOk(doc->setField(box, "metallic", "0.5", true)));
    doc->undo();
    EXPECT_EQ(field(*doc, box, "roughness"), "0.300000012");
    EXPECT_EQ(field(*doc, box, "metallic"), "0");
}

TEST(Document, ApplyIsAllOrNothingAndErrorsListWhatIsValid) {
    TempDir dir;
    auto doc = openDoc(copyScene(dir, "grazing-plane"));
    ASSERT_TRUE(doc);
    const auto before = encodedMaterials(*doc);
    const uint32_t box = materialIndex(doc->scene(), "box"),
                   pole = materialIndex(doc->scene(), "pole");

    // The second edit is invalid: the first must not happen either.
    Status s = doc->apply({{box, "roughness", "0.1"}, {pole, "roughness", "7"}});
    ASSERT_FALSE(isOk(s));
    EXPECT_NE(s.message.find("[0, 1]"), std::string::npos) << s.message;
    EXPECT_NE(s.message.find("'pole'"), std::string::npos) << "names the material: " << s.message;
    EXPECT_EQ(encodedMaterials(*doc), before);
    EXPECT_FALSE(doc->dirty());
    EXPECT_FALSE(doc->canUndo());

    s = doc->apply({{box, "roughnes", "0.1"}});
    ASSERT_FALSE(isOk(s));
    for (const MaterialField& f : materialFields())
        EXPECT_NE(s.message.find(f.name), std::string::npos) << "lists " << f.name;
    s = doc->apply({{99, "roughness", "0.1"}});
    ASSERT_FALSE(isOk(s));
    EXPECT_NE(s.message.find("0..3"), std::string::npos) << s.message;
    s = doc->setField(box, "alpha_mode", "glass");
    EXPECT_NE(s.message.find("opaque|mask|blend"), std::string::npos) << s.message;
    s = doc->setField(box, "base_color_texture", "7");
    ASSERT_FALSE(isOk(s));
    EXPECT_NE(s.message.find("0 'checker'"), std::string::npos) << s.message;
    s = doc->setField(box, "base_color_texture", "marble");
    ASSERT_FALSE(isOk(s));
    EXPECT_NE(s.message.find("no texture has this name"), std::string::npos) << s.message;
    EXPECT_NE(s.message.find("0 'checker'"), std::string::npos) << s.message;
    EXPECT_EQ(encodedMaterials(*doc), before);
    EXPECT_FALSE(doc->canUndo());

    // A valid batch is one undo step.
    ASSERT_TRUE(isOk(doc->apply({{box, "roughness", "0.1"}, {pole, "layer_priority", "2"}})));
    EXPECT_EQ(field(*doc, box, "roughness"), "0.100000001");
    EXPECT_EQ(field(*doc, pole, "layer_priority"), "2");
    doc->undo();
    EXPECT_EQ(encodedMaterials(*doc), before);
}

TEST(Document, MissingStreamsAreClearErrors) {
    TempDir dir;
    auto doc = openDoc(copyScene(dir, "grazing-plane"));
    ASSERT_TRUE(doc);
    const uint32_t plane = materialIndex(doc->scene(), "checker-plane"),
                   pole = materialIndex(doc->scene(), "pole");
    // The plane has UVs but no tangents (nothing was normal-mapped).
    Status s = doc->setField(plane, "normal_texture", "checker");
    ASSERT_FALSE(isOk(s));
    EXPECT_NE(s.message.find("tangent"), std::string::npos) << s.message;
    EXPECT_NE(s.message.find("'plane'"), std::string::npos) << "names the mesh: " << s.message;
    EXPECT_NE(s.message.find("reconvert"), std::string::npos) << s.message;
    // The poles have no UVs at all.
    s = doc->setField(pole, "base_color_texture", "0");
    ASSERT_FALSE(isOk(s));
    EXPECT_NE(s.message.find("TEXCOORD_0"), std::string::npos) << s.message;
    EXPECT_FALSE(doc->dirty());
    // What the mesh has is fine: another slot on the plane's UVs.
    EXPECT_TRUE(isOk(doc->setField(plane, "occlusion_texture", "checker")));
}

TEST(Document, LayerOrder) {
    TempDir dir;
    auto doc = openDoc(copyScene(dir, "box-room"));
    ASSERT_TRUE(doc);
    const Scene& s = doc->scene();
    uint32_t forwardCount = 0;
    for (const Material& m : s.materials) forwardCount += m.shadingPath == ShadingPath::Forward;
    ASSERT_GT(forwardCount, 0u) << "the box room's glass is forward";
    ASSERT_TRUE(isOk(doc->apply({{0, "layer_priority", "5"}, {1, "layer_priority", "2"}})));
    auto order = doc->layerOrder();
    EXPECT_EQ(order.forward.size(), forwardCount);
    ASSERT_GE(order.deferred.size(), 2u);
    for (size_t k = 1; k < order.deferred.size(); ++k)
        EXPECT_LT(order.deferred[k - 1].first, order.deferred[k].first) << "ascending";
    EXPECT_EQ(order.deferred.back().first, 5);
    EXPECT_EQ(order.deferred.back().second, std::vector<uint32_t>{0});
    size_t listed = order.forward.size();
    for (const auto& layer : order.deferred) listed += layer.second.size();
    EXPECT_EQ(listed, doc->materialCount());
}

// The program an edited material gets is the converter's for the same material: convert the
// same source with a sidecar that makes the edit, and compare. `sky`: both with an environment
// (the lighting programs then carry IBL).
void expectProgramsMatchTheConverter(bool sky) {
    TempDir dir;
    const auto source = editorScene();
    const std::string plainFile = convert(dir, source, "plain", "", sky);
    const std::string sidecar = R"({ "materials": {
        "textured": { "shading_path": "forward", "alpha_mode": "mask" },
        "plain": { "casts_shadows": false, "layer_priority": 3 },
        "glass": { "shading_path": "deferred", "layer_priority": 1 } } })";
    const std::string placedFile = convert(dir, source, "placed", sidecar, sky);

    auto doc = openDoc(plainFile);
    ASSERT_TRUE(doc);
    const Scene& edited = doc->scene();
    Opened placed = openScene(placedFile);
    ASSERT_TRUE(isOk(doc->apply({{materialIndex(edited, "textured"), "shading_path", "forward"},
                                 {materialIndex(edited, "textured"), "alpha_mode", "mask"},
                                 {materialIndex(edited, "plain"), "casts_shadows", "false"},
                                 {materialIndex(edited, "plain"), "layer_priority", "3"},
                                 {materialIndex(edited, "glass"), "shading_path", "deferred"},
                                 {materialIndex(edited, "glass"), "layer_priority", "1"}})));
    for (const char* name : {"textured", "plain", "glass", "leaf"}) {
        const Material& a = edited.materials[materialIndex(edited, name)];
        const Material& b = placed.scene.materials[materialIndex(placed.scene, name)];
        EXPECT_EQ(describeProgram(edited, a.program), describeProgram(placed.scene, b.program))
            << name;
        Material x = a, y = b;
        x.program = y.program = kNone;
        x.name = y.name = kNone; // string tables differ
        EXPECT_EQ(encodeChunk(x), encodeChunk(y)) << name << ": same fields as the sidecar's";
    }
    // Every program the converter packs for the placed scene exists in the edited document, and
    // the stage sources the editor added are the converter's, byte for byte.
    for (uint32_t p = 0; p < placed.scene.programs.size(); ++p) {
        bool found = false;
        for (uint32_t q = 0; q < edited.programs.size() && !found; ++q)
            found = describeProgram(edited, q) == describeProgram(placed.scene, p);
        EXPECT_TRUE(found) << describeProgram(placed.scene, p);
    }
    for (const ShaderSource& sh : edited.shaders)
        for (const ShaderSource& ref : placed.scene.shaders)
            if (edited.str(sh.name) == placed.scene.str(ref.name)) {
                EXPECT_TRUE(std::equal(sh.source.begin(), sh.source.end(), ref.source.begin(),
                                       ref.source.end()))
                    << edited.str(sh.name);
            }
    // Saved, it is a valid file whose programs are what the document showed.
    const std::string out = dir.file("edited.pnb");
    auto saved = doc->save(out);
    ASSERT_TRUE(saved.ok()) << saved.error().describe();
    Opened reread = openScene(out);
    for (const char* name : {"textured", "plain", "glass", "leaf"})
        EXPECT_EQ(describeProgram(reread.scene,
                                  reread.scene.materials[materialIndex(reread.scene, name)].program),
                  describeProgram(placed.scene,
                                  placed.scene.materials[materialIndex(placed.scene, name)].program))
            << name;
    bool ibl = false;
    for (uint32_t p = 0; p < reread.scene.programs.size(); ++p)
        ibl |= describeProgram(reread.scene, p).find("IBL") != std::string::npos;
    EXPECT_EQ(ibl, sky);
}

TEST(Document, ProgramsMatchTheConverter) { expectProgramsMatchTheConverter(false); }
TEST(Document, ProgramsMatchTheConverterWithAnEnvironment) { expectProgramsMatchTheConverter(true); }

TEST(Document, SceneLevelProgramsOnlyWhenAnEditNeedsThem) {
    TempDir dir;
    auto doc = openDoc(copyScene(dir, "grazing-plane"));
    ASSERT_TRUE(doc);
    const size_t programs = doc->scene().programs.size(), shaders = doc->scene().shaders.size();
    const uint32_t plane = materialIndex(doc->scene(), "checker-plane");
    // Alpha-masked shadow caster: a masked G-buffer variant and the masked shadow program.
    ASSERT_TRUE(isOk(doc->setField(plane, "alpha_mode", "mask")));
    const Scene& s = doc->scene();
    ASSERT_EQ(s.programs.size(), programs + 2);
    EXPECT_EQ(describeProgram(s, s.materials[plane].program),
              "gbuffer[ALPHA_MASK HAS_BASE_COLOR_MAP HAS_UV0] surface.vert+gbuffer.frag");
    EXPECT_EQ(describeProgram(s, uint32_t(programs + 1)),
              "shadow[ALPHA_MASK] shadow.vert+shadow.frag");
    EXPECT_EQ(s.shaders.size(), shaders) << "stages reused, none added";
    // The plane stops casting shadows: the masked shadow program is no longer needed.
    ASSERT_TRUE(isOk(doc->setField(plane, "casts_shadows", "false")));
    EXPECT_EQ(doc->scene().programs.size(), programs + 1);
    // Undo brings it back.
    doc->undo();
    EXPECT_EQ(doc->scene().programs.size(), programs + 2);
    doc->undo();
    EXPECT_EQ(doc->scene().programs.size(), programs);
    EXPECT_TRUE(isOk(validateScene(doc->scene())));
}

// Issue 43: casts_shadows on a BLEND material adds the translucent shadow program and the
// lighting programs' TRANSLUCENT_SHADOWS, as the converter writes them; undo takes them away.
TEST(Document, BlendedCasterAddsTheTranslucentShadowProgram) {
    TempDir dir;
    const auto source = editorScene();
    const std::string opaqueOnly =
        convert(dir, source, "opaque-only", R"({ "materials": { "glass": { "casts_shadows": false } } })");
    const std::string withGlass = convert(dir, source, "with-glass");
    auto doc = openDoc(opaqueOnly);
    ASSERT_TRUE(doc);
    auto programNames = [](const Scene& s) {
        std::vector<std::string> names;
        for (uint32_t p = 0; p < s.programs.size(); ++p) names.push_back(describeProgram(s, p));
        return names;
    };
    auto hasTranslucent = [&](const Scene& s) {
        for (const std::string& n : programNames(s))
            if (n.find("TRANSLUCENT") != std::string::npos) return true;
        return false;
    };
    EXPECT_FALSE(hasTranslucent(doc->scene())) << "no blended caster: no variant, no define";
    const size_t programs = doc->scene().programs.size();
    const uint32_t glass = materialIndex(doc->scene(), "glass");
    ASSERT_TRUE(isOk(doc->setField(glass, "casts_shadows", "true")));
    Opened converted = openScene(withGlass);
    ASSERT_TRUE(hasTranslucent(converted.scene));
    const std::vector<std::string> edited = programNames(doc->scene());
    for (const std::string& n : programNames(converted.scene))
        EXPECT_NE(std::find(edited.begin(), edited.end(), n), edited.end()) << n << " as the converter writes it";
    for (const char* name : {"textured", "plain", "glass", "leaf"})
        EXPECT_EQ(describeProgram(doc->scene(), doc->scene().materials[materialIndex(doc->scene(), name)].program),
                  describeProgram(converted.scene,
                                  converted.scene.materials[materialIndex(converted.scene, name)].program))
            << name;
    EXPECT_TRUE(isOk(validateScene(doc->scene())));
    doc->undo();
    EXPECT_EQ(doc->scene().programs.size(), programs);
    EXPECT_FALSE(hasTranslucent(doc->scene()));
}

// An edit the player cannot show is named, never silently accepted.
TEST(Document, EditsWithoutEffectSayWhy) {
    TempDir dir;
    auto doc = openDoc(convert(dir, editorScene(), "lit"));
    ASSERT_TRUE(doc);
    const Scene& s = doc->scene();
    const uint32_t plain = materialIndex(s, "plain"), glass = materialIndex(s, "glass"),
                   leaf = materialIndex(s, "leaf");
    EXPECT_EQ(doc->noEffectReason(plain, "receives_shadows"), "");
    EXPECT_EQ(doc->noEffectReason(plain, "casts_shadows"), "");
    EXPECT_EQ(doc->noEffectReason(plain, "roughness"), "");
    // Blended casters tint the light through them (issue 43): the flag matters on glass too.
    EXPECT_EQ(doc->noEffectReason(glass, "casts_shadows"), "");
    EXPECT_EQ(doc->noEffectReason(glass, "receives_shadows"), "") << "forward honours it";
    EXPECT_NE(doc->noEffectReason(plain, "alpha_cutoff").find("mask only"), std::string::npos);
    EXPECT_EQ(doc->noEffectReason(leaf, "alpha_cutoff"), "");
    ASSERT_TRUE(isOk(doc->setField(plain, "alpha_mode", "mask")));
    EXPECT_EQ(doc->noEffectReason(plain, "alpha_cutoff"), "");

    // Nothing casts any more: receiving shadows has no effect anywhere.
    std::vector<Document::FieldEdit> noCasters;
    for (uint32_t m = 0; m < doc->materialCount(); ++m) noCasters.push_back({m, "casts_shadows", "false"});
    ASSERT_TRUE(isOk(doc->apply(noCasters)));
    EXPECT_NE(doc->noEffectReason(plain, "receives_shadows").find("no material casts shadows"),
              std::string::npos);
}

TEST(Document, ImportTexture) {
    TempDir dir;
    auto doc = openDoc(copyScene(dir, "grazing-plane"));
    ASSERT_TRUE(doc);
    writeBytes(dir.file("stripes.png"), checkerPng(40, {255, 0, 0}, {0, 0, 255}));
    const size_t textures = doc->scene().textures.size();
    auto t = doc->importTexture(dir.file("stripes.png"), true);
    ASSERT_TRUE(t.ok()) << t.error().describe();
    EXPECT_EQ(*t, textures);
    const Scene& s = doc->scene();
    ASSERT_EQ(s.textures.size(), textures + 1);
    EXPECT_EQ(s.str(s.textures[*t].name), "stripes");
    EXPECT_EQ(s.textures[*t].width, 40u);
    EXPECT_EQ(s.textures[*t].colorSpace, ColorSpace::Srgb);
    EXPECT_EQ(s.textures[*t].mipCount, 6u) << "40, 20, 10, 5, 2, 1";
    EXPECT_TRUE(doc->dirty());
    EXPECT_TRUE(isOk(validateScene(s)));
    // The same stem again gets a unique name; an explicit duplicate name is an error.
    auto again = doc->importTexture(dir.file("stripes.png"), false);
    ASSERT_TRUE(again.ok());
    EXPECT_EQ(doc->scene().str(doc->scene().textures[*again].name), "stripes-2");
    EXPECT_EQ(doc->scene().textures[*again].colorSpace, ColorSpace::Linear);
    auto dup = doc->importTexture(dir.file("stripes.png"), true, "checker");
    ASSERT_FALSE(dup.ok());
    EXPECT_NE(dup.error().message.find("already exists"), std::string::npos);
    auto missing = doc->importTexture(dir.file("none.png"), true);
    ASSERT_FALSE(missing.ok());
    EXPECT_NE(missing.error().message.find("none.png"), std::string::npos);

    // By name in a texture slot. Undo removes the slot edit, then the imports.
    const uint32_t plane = materialIndex(doc->scene(), "checker-plane");
    ASSERT_TRUE(isOk(doc->setField(plane, "base_color_texture", "stripes")));
    EXPECT_EQ(doc->scene().materials[plane].textures[0].texture, *t);
    doc->undo();
    doc->undo();
    doc->undo();
    EXPECT_EQ(doc->scene().textures.size(), textures);
    EXPECT_EQ(doc->scene().textureMips.size(), 7u);
    EXPECT_FALSE(doc->dirty());
    doc->redo();
    doc->redo();
    doc->redo();
    EXPECT_EQ(doc->scene().materials[plane].textures[0].texture, *t);
    EXPECT_TRUE(isOk(validateScene(doc->scene())));
}

} // namespace

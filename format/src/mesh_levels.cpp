// Level-of-detail chains of a mesh's submeshes (the pairing rule is in pnb/mesh_levels.h).
#include "pnb/mesh_levels.h"

#include <cstring>
#include <map>
#include <unordered_map>

namespace pnb {

std::vector<SubmeshChain> buildLevelChains(std::span<const Submesh> submeshes) {
    std::vector<SubmeshChain> chains;
    // Per material: its chains (indices into `chains`) and, per level, its submeshes in order.
    std::map<uint32_t, std::vector<size_t>> chainsOf;
    std::map<std::pair<uint32_t, uint32_t>, std::vector<uint32_t>> byLevel; // (material, lod)
    for (uint32_t s = 0; s < submeshes.size(); ++s) {
        const Submesh& sm = submeshes[s];
        if (sm.material == kNone) continue;
        if (sm.lod == 0) {
            chainsOf[sm.material].push_back(chains.size());
            chains.push_back({sm.material, {s}});
        } else {
            byLevel[{sm.material, sm.lod}].push_back(s);
        }
    }
    for (const auto& [material, own] : chainsOf) {
        for (uint32_t level = 1; level <= 255; ++level) {
            auto it = byLevel.find({material, level});
            if (it == byLevel.end() || it->second.size() != own.size()) break;
            for (size_t j = 0; j < own.size(); ++j) chains[own[j]].levels.push_back(it->second[j]);
        }
    }
    return chains;
}

bool hasLevelChains(const Mesh& mesh) {
    for (const SubmeshChain& c : buildLevelChains(mesh.submeshes))
        if (c.levels.size() > 1) return true;
    return false;
}

Mesh buildCoarseProxy(const Mesh& mesh, SceneBuilder& builder) {
    Mesh proxy = mesh;
    proxy.submeshes.clear();
    std::unordered_map<uint32_t, uint32_t> remap; // mesh vertex -> proxy vertex
    std::vector<uint32_t> used;                   // proxy vertex -> mesh vertex
    std::vector<uint32_t> indices;
    for (const SubmeshChain& chain : buildLevelChains(mesh.submeshes)) {
        const Submesh& coarse = mesh.submeshes[chain.levels.back()];
        Submesh sm = mesh.submeshes[chain.levels.front()]; // material, bounds of level 0
        sm.firstIndex = uint32_t(indices.size());
        sm.indexCount = coarse.indexCount;
        sm.lod = 0;
        sm.lodError = 0;
        for (uint32_t k = coarse.firstIndex; k < coarse.firstIndex + coarse.indexCount; ++k) {
            const uint32_t v = meshIndex(mesh, k);
            auto [it, added] = remap.emplace(v, uint32_t(used.size()));
            if (added) used.push_back(v);
            indices.push_back(it->second);
        }
        proxy.submeshes.push_back(sm);
    }
    proxy.vertexCount = uint32_t(used.size());
    for (VertexStream& s : proxy.streams) {
        const size_t stride = componentSizeBytes(s.componentType) * s.componentCount;
        std::vector<std::byte> data(used.size() * stride);
        for (size_t v = 0; v < used.size(); ++v)
            std::memcpy(data.data() + v * stride, s.data.data() + size_t(used[v]) * stride, stride);
        s.data = builder.keep(data);
    }
    if (proxy.indexType == IndexType::U16) {
        std::vector<uint16_t> narrow(indices.begin(), indices.end());
        proxy.indices = builder.keep(narrow);
    } else {
        proxy.indices = builder.keep(indices);
    }
    return proxy;
}

} // namespace pnb

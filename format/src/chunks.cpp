// Generic field codec for the typed chunk payloads (FORMAT.md §4.2). Each struct's fields(v)
// list drives the Encoder, the Decoder and the minimum-size computation, so there is one
// description of every layout.

#include "pnb/chunks.h"

#include <algorithm>
#include <cstdarg>
#include <cstdio>
#include <string>
#include <type_traits>

#include "bytes.h"
#include "pnb/writer.h"

namespace pnb {

namespace {

constexpr size_t kBlobAlignment = 16;

template <class T> struct IsVector : std::false_type {};
template <class T> struct IsVector<std::vector<T>> : std::true_type {};
template <class T> struct IsArray : std::false_type {};
template <class T, size_t N> struct IsArray<std::array<T, N>> : std::true_type {};

template <class T> T& mut(const T& v) { return const_cast<T&>(v); } // fields() is non-const

class Encoder {
public:
    std::vector<std::byte> out;

    template <class T> void operator()(const T& v) {
        if constexpr (std::is_same_v<T, SinceVersion>) {
            // nothing stored: the marker only tells an older chunk's decoder where to stop
        } else if constexpr (std::is_same_v<T, bool>) {
            put<uint8_t>(v ? 1 : 0);
        } else if constexpr (std::is_enum_v<T>) {
            put(static_cast<std::underlying_type_t<T>>(v));
        } else if constexpr (std::is_arithmetic_v<T>) {
            put(v);
        } else if constexpr (std::is_same_v<T, Blob>) {
            put<uint64_t>(v.size());
            out.resize((out.size() + kBlobAlignment - 1) / kBlobAlignment * kBlobAlignment);
            out.insert(out.end(), v.begin(), v.end());
        } else if constexpr (std::is_same_v<T, std::string_view>) {
            put<uint32_t>(uint32_t(v.size()));
            auto* p = reinterpret_cast<const std::byte*>(v.data());
            out.insert(out.end(), p, p + v.size());
        } else if constexpr (IsVector<T>::value) {
            put<uint32_t>(uint32_t(v.size()));
            for (const auto& e : v) (*this)(e);
        } else if constexpr (IsArray<T>::value) {
            for (const auto& e : v) (*this)(e);
        } else {
            mut(v).fields(*this);
        }
    }

private:
    template <class T> void put(T v) {
        size_t at = out.size();
        out.resize(at + sizeof(T));
        detail::storeLE<T>(out.data() + at, v);
    }
};

// Encoded size of a default-constructed T: a lower bound for any encoded T, used to bound
// array counts before allocating (a count can never need more bytes than remain).
template <class T> size_t minEncodedSize() {
    static const size_t size = [] {
        Encoder e;
        e(T{});
        return e.out.size();
    }();
    return size;
}

class Decoder {
public:
    Decoder(std::span<const std::byte> in, uint64_t base, const char* chunk,
            uint16_t version = 0xFFFF)
        : mIn(in), mBase(base), mChunk(chunk), mVersion(version) {}

    bool ok() const { return isOk(mError); }
    const Error& error() const { return mError; }
    size_t pos() const { return mPos; }

    // Fields appended after the chunk's version: not in the payload, left at their defaults.
    void operator()(const SinceVersion& s) {
        if (s.version > mVersion) mOlder = true;
    }

    template <class T> void operator()(T& v) {
        if (!ok() || mOlder) return;
        if constexpr (std::is_same_v<T, bool>) {
            uint8_t b = 0;
            if (get(b) && b > 1) fail("boolean byte %u is not 0 or 1", b);
            v = b == 1;
        } else if constexpr (std::is_enum_v<T>) {
            std::underlying_type_t<T> u{};
            if (get(u) && u >= static_cast<std::underlying_type_t<T>>(T::Count))
                fail("enum value %u out of range (%u values)", unsigned(u), unsigned(T::Count));
            v = static_cast<T>(u);
        } else if constexpr (std::is_arithmetic_v<T>) {
            get(v);
        } else if constexpr (std::is_same_v<T, Blob>) {
            uint64_t size = 0;
            if (!get(size)) return;
            size_t aligned = (mPos + kBlobAlignment - 1) / kBlobAlignment * kBlobAlignment;
            if (aligned > mIn.size()) return fail("blob padding runs past the payload");
            for (size_t i = mPos; i < aligned; ++i)
                if (mIn[i] != std::byte{0}) return fail("blob padding is not zero");
            mPos = aligned;
            if (size > mIn.size() - mPos)
                return fail("blob of %llu bytes runs past the payload", (unsigned long long)size);
            v = mIn.subspan(mPos, size_t(size));
            mPos += size_t(size);
        } else if constexpr (std::is_same_v<T, std::string_view>) {
            uint32_t size = 0;
            if (!get(size)) return;
            if (size > mIn.size() - mPos)
                return fail("string of %u bytes runs past the payload", size);
            v = std::string_view(reinterpret_cast<const char*>(mIn.data() + mPos), size);
            mPos += size;
        } else if constexpr (IsVector<T>::value) {
            using E = typename T::value_type;
            uint32_t count = 0;
            if (!get(count)) return;
            size_t minSize = std::max<size_t>(1, minEncodedSize<E>());
            if (count > (mIn.size() - mPos) / minSize)
                return fail("array of %u elements cannot fit in the %zu bytes left", count,
                            mIn.size() - mPos);
            v.assign(count, E{});
            for (size_t k = 0; k < v.size(); ++k) {
                (*this)(v[k]);
                if (!ok()) {
                    // Which record: "LGHT payload: enum value 7 out of range (3 values), in
                    // element 2 of 5" names the light (nested arrays add one clause each).
                    mError.message += ", in element " + std::to_string(k) + " of " + std::to_string(count);
                    return;
                }
            }
        } else if constexpr (IsArray<T>::value) {
            for (auto& e : v) (*this)(e);
        } else {
            v.fields(*this);
        }
    }

    void fail(const char* fmt, ...) __attribute__((format(printf, 2, 3))) {
        if (!ok()) return;
        char buf[256];
        va_list args;
        va_start(args, fmt);
        std::vsnprintf(buf, sizeof(buf), fmt, args);
        va_end(args);
        mError = makeError(FormatError::BadPayload, mBase + mPos, "%s payload: %s", mChunk, buf);
    }

private:
    template <class T> bool get(T& v) {
        if (mIn.size() - mPos < sizeof(T)) {
            fail("ends early (field at payload byte %zu of %zu)", mPos, mIn.size());
            return false;
        }
        v = detail::loadLE<T>(mIn.data() + mPos);
        mPos += sizeof(T);
        return true;
    }

    std::span<const std::byte> mIn;
    uint64_t mBase;
    const char* mChunk;
    uint16_t mVersion;    // the chunk's version
    bool mOlder = false;  // past a SinceVersion newer than the chunk: decode nothing more
    size_t mPos = 0;
    Error mError;
};

} // namespace

template <class T> std::vector<std::byte> encodeChunk(const T& value) {
    Encoder e;
    e(value);
    return std::move(e.out);
}

template <class T>
Result<T> decodeChunk(std::span<const std::byte> payload, const ChunkHeader& header,
                      uint64_t offset) {
    const std::string tag = ChunkTraits<T>::tag.str();
    const uint16_t known = ChunkTraits<T>::version;
    const bool newer = header.version > known;
    if (header.version == 0 || (newer && (header.flags & kChunkCritical)))
        return makeError(FormatError::UnsupportedChunkVersion, offset,
                         "'%s' chunk version %u%s, this reader supports 1..%u%s", tag.c_str(),
                         header.version, newer ? " (critical)" : "", known,
                         newer ? ": update Penumbra to read it" : "");
    T value{};
    Decoder d(payload, offset, tag.c_str(), header.version);
    d(value);
    // Bytes after the known fields are a newer version's appended fields; in a version this
    // reader knows they can only be damage.
    if (d.ok() && !newer && d.pos() != payload.size())
        d.fail("%zu bytes left over after the last field", payload.size() - d.pos());
    if (!d.ok()) return d.error();
    return value;
}

// FORMAT.md 3.5 rule 6: a chunk whose appended fields change what an older reader would draw
// is written critical, so that reader refuses it instead of drawing it wrong.
template <class T> bool isCritical(const T&) { return false; }
bool isCritical(const Material& m) { return m.unlit; }
bool isCritical(const NodeGraph& g) { return !g.instances.empty(); }

template <class T> Status writeChunk(Writer& writer, const T& value, Compression compression) {
    return writer.addChunk(ChunkTraits<T>::tag, ChunkTraits<T>::version, encodeChunk(value),
                           compression, isCritical(value));
}

#define PNB_INSTANTIATE(Type)                                                                      \
    template std::vector<std::byte> encodeChunk<Type>(const Type&);                                \
    template Result<Type> decodeChunk<Type>(std::span<const std::byte>, const ChunkHeader&,         \
                                            uint64_t);                                             \
    template Status writeChunk<Type>(Writer&, const Type&, Compression);
PNB_INSTANTIATE(StringTable)
PNB_INSTANTIATE(SceneInfo)
PNB_INSTANTIATE(RenderSettings)
PNB_INSTANTIATE(ShaderSource)
PNB_INSTANTIATE(Program)
PNB_INSTANTIATE(TextureDesc)
PNB_INSTANTIATE(TextureMip)
PNB_INSTANTIATE(Material)
PNB_INSTANTIATE(Mesh)
PNB_INSTANTIATE(MorphTargets)
PNB_INSTANTIATE(Skin)
PNB_INSTANTIATE(Animation)
PNB_INSTANTIATE(LightList)
PNB_INSTANTIATE(CameraList)
PNB_INSTANTIATE(NodeGraph)
PNB_INSTANTIATE(CameraPath)
PNB_INSTANTIATE(MeshDetail)
PNB_INSTANTIATE(Environment)
#undef PNB_INSTANTIATE

size_t meshIndexCount(const Mesh& mesh) {
    return mesh.indices.size() / (mesh.indexType == IndexType::U16 ? 2 : 4);
}

uint32_t meshIndex(const Mesh& mesh, size_t k) {
    return mesh.indexType == IndexType::U16 ? detail::loadLE<uint16_t>(&mesh.indices[k * 2])
                                            : detail::loadLE<uint32_t>(&mesh.indices[k * 4]);
}

uint32_t componentSizeBytes(ComponentType t) {
    switch (t) {
    case ComponentType::I8:
    case ComponentType::U8: return 1;
    case ComponentType::F16:
    case ComponentType::I16:
    case ComponentType::U16: return 2;
    case ComponentType::F32:
    case ComponentType::I32:
    case ComponentType::U32: return 4;
    case ComponentType::Count: break;
    }
    return 0;
}

uint64_t textureLevelSizeBytes(TextureFormat f, uint32_t width, uint32_t height, uint32_t layers) {
    uint64_t w = width, h = height;
    uint64_t blocks = ((w + 3) / 4) * ((h + 3) / 4) * layers;
    uint64_t texels = w * h * layers;
    switch (f) {
    case TextureFormat::R8: return texels;
    case TextureFormat::RG8: return texels * 2;
    case TextureFormat::RGB8: return texels * 3;
    case TextureFormat::RGBA8: return texels * 4;
    case TextureFormat::R16F: return texels * 2;
    case TextureFormat::RG16F: return texels * 4;
    case TextureFormat::RGBA16F: return texels * 8;
    case TextureFormat::R32F: return texels * 4;
    case TextureFormat::RG32F: return texels * 8;
    case TextureFormat::RGBA32F: return texels * 16;
    case TextureFormat::BC1:
    case TextureFormat::BC4: return blocks * 8;
    case TextureFormat::BC3:
    case TextureFormat::BC5:
    case TextureFormat::BC7: return blocks * 16;
    case TextureFormat::Count: break;
    }
    return 0;
}

} // namespace pnb

// CompressionMemo (pnb/compression_memo.h) and the Writer using it: the bytes written are the
// same with and without the memo, a second container reuses the first one's frames, and the
// memo keeps to its limits and never confuses payloads or levels.
#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "format_test_util.h"
#include "pnb/compression_memo.h"

namespace {

using namespace pnb;
using namespace pnb::test;

std::vector<std::byte> bytesOf(std::string_view text) {
    std::vector<std::byte> out(text.size());
    std::memcpy(out.data(), text.data(), text.size());
    return out;
}

TEST(CompressionMemo, WriterOutputIsTheSameWithTheMemoAndReusesFrames) {
    const std::vector<std::byte> plain = sampleBytes();
    WriteOptions options;
    options.compressionMemo = std::make_shared<CompressionMemo>();
    const std::vector<std::byte> first = sampleBytes(options);
    EXPECT_EQ(options.compressionMemo->hits(), 0u);
    const std::vector<std::byte> second = sampleBytes(options);
    EXPECT_GT(options.compressionMemo->hits(), 0u) << "the second container reused frames";
    EXPECT_EQ(first, plain);
    EXPECT_EQ(second, plain);
    // A different level is a different frame: not taken from the memo.
    options.zstdLevel = 1;
    WriteOptions level1;
    level1.zstdLevel = 1;
    EXPECT_EQ(sampleBytes(options), sampleBytes(level1));
}

TEST(CompressionMemo, FindsOnlyTheSamePayloadAtTheSameLevel) {
    CompressionMemo memo(64, 200);
    const auto a = bytesOf("payload a"), b = bytesOf("payload b"), frame = bytesOf("frame");
    memo.remember(a, 9, frame);
    ASSERT_TRUE(memo.find(a, 9).has_value());
    EXPECT_EQ(*memo.find(a, 9), frame);
    EXPECT_FALSE(memo.find(a, 3).has_value());
    EXPECT_FALSE(memo.find(b, 9).has_value());
    EXPECT_EQ(memo.hits(), 2u);
    // Larger than maxEntryBytes: never remembered.
    const std::vector<std::byte> big(65, std::byte{7});
    memo.remember(big, 9, frame);
    EXPECT_FALSE(memo.find(big, 9).has_value());
    // Full (200 bytes of payloads and frames): new entries are not remembered.
    const std::vector<std::byte> c(60, std::byte{1}), d(60, std::byte{2});
    memo.remember(c, 9, c); // 120 + 14 held
    memo.remember(d, 9, d); // would pass 200
    EXPECT_TRUE(memo.find(c, 9).has_value());
    EXPECT_FALSE(memo.find(d, 9).has_value());
}

} // namespace

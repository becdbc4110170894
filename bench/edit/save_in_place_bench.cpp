// pnb_edit_bench: what an in-place pnb-edit save costs against a durable copy of the same file,
// both measured in this run. The save in place is the path that guards against another writer
// (the target's advisory lock and the compare-before-rename of pnb/file_lock.h), so this is
// where that guard's cost would show. Scene: the build-time terrain.pnb (9.3 MiB), copied to a
// temporary directory; each iteration flips one material's roughness and saves in place.
//
//   pnb_edit_bench [--benchmark_repetitions=N ...]
#include <benchmark/benchmark.h>

#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "pnb_editor/document.h"

namespace {

namespace fs = std::filesystem;

std::string workCopy(const char* name) {
    static const std::string dir = [] {
        std::string tmpl = fs::temp_directory_path().string() + "/pnb-edit-bench-XXXXXX";
        if (::mkdtemp(tmpl.data()) == nullptr) std::abort();
        return tmpl;
    }();
    const std::string target = dir + "/" + name;
    fs::copy_file(std::string(PNB_SCENE_DIR) + "/terrain.pnb", target,
                  fs::copy_options::overwrite_existing);
    return target;
}

void BM_CopyWithFsync(benchmark::State& state) {
    const std::string source = workCopy("source.pnb"), copy = source + ".copy";
    for (auto _ : state) {
        fs::copy_file(source, copy, fs::copy_options::overwrite_existing);
        int fd = ::open(copy.c_str(), O_RDONLY | O_CLOEXEC);
        ::fsync(fd);
        ::close(fd);
    }
    state.SetBytesProcessed(int64_t(state.iterations()) * int64_t(fs::file_size(source)));
}

void BM_SaveInPlace(benchmark::State& state) {
    auto doc = pnb::editor::Document::open(workCopy("edited.pnb"));
    if (!doc) {
        state.SkipWithError(doc.error().message.c_str());
        return;
    }
    int round = 0;
    for (auto _ : state) {
        if (!pnb::isOk((*doc)->setField(0, "roughness", ++round % 2 ? "0.25" : "0.75")) ||
            !(*doc)->save().ok()) {
            state.SkipWithError("edit or save failed");
            return;
        }
    }
    state.SetBytesProcessed(int64_t(state.iterations()) * int64_t(fs::file_size((*doc)->path())));
}

BENCHMARK(BM_CopyWithFsync)->Unit(benchmark::kMillisecond)->MinTime(1.0);
BENCHMARK(BM_SaveInPlace)->Unit(benchmark::kMillisecond)->MinTime(1.0);

} // namespace

BENCHMARK_MAIN();

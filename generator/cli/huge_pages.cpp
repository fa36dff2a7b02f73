#include "cli/huge_pages.hpp"

#include <cstddef>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <system_error>
#if defined(__GLIBC__)  // defined by the C++ library's headers above
#include <malloc.h>
#include <sys/mman.h>
#include <unistd.h>
#endif

namespace cs {

namespace {

// The first kHugeHeap of the main heap, reserved at once (address space only) and marked
// MADV_HUGEPAGE, takes 2 MB pages: igea (270k triangles) 39.5k -> 5.9k page faults and 2.1 -> 1.6
// CPU-s on the bench machine, the same as with glibc.malloc.hugetlb=1. Where the kernel's
// transparent huge pages are off, the advice does nothing. Under M_TRIM_THRESHOLD
// (tune_allocator), so glibc keeps it when it is free.
constexpr std::size_t kHugeHeap = std::size_t{256} << 20;
constexpr std::size_t kHugePage = std::size_t{2} << 20;

void heap_on_huge_pages() {
#if defined(__GLIBC__)
    const auto brk_now = [] { return reinterpret_cast<std::uintptr_t>(sbrk(0)); };
    const std::uintptr_t before = brk_now();
    mallopt(M_TOP_PAD, static_cast<int>(kHugeHeap));
    void* volatile grow = malloc(std::size_t{1} << 20);  // the heap grows by it and the pad
    free(grow);
    mallopt(M_TOP_PAD, 128 << 10);  // glibc's default again
    const std::uintptr_t lo = (before + kHugePage - 1) / kHugePage * kHugePage, hi = brk_now() / kHugePage * kHugePage;
    if (hi > lo) madvise(reinterpret_cast<void*>(lo), hi - lo, MADV_HUGEPAGE);
#endif
}

std::string read_thp_mode() {
    std::ifstream in("/sys/kernel/mm/transparent_hugepage/enabled");
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace

// One run builds and drops many buffers of megabytes (the mesh, its index, the 3MF XML and its
// deflated package, the STLs). glibc maps each one above 128 KB fresh from the kernel and unmaps it
// on free, so every run pays the page faults again, and it hands the top of the heap back as soon
// as 128 KB are free there. Keeping buffers up to 32 MB on the heap and freed memory up to 512 MB:
// igea (270k triangles) 2.5 -> 2.0 CPU-s, peak memory +9 %. Then the heap on huge pages.
//
// One arena for every thread (M_ARENA_MAX 1): glibc gives each thread of the orientation search an
// arena of its own, heaps of 64 MB mapped apart from the main heap, neither kept when freed nor on
// huge pages, so each candidate pose's buffers were faulted in afresh. On the bench machine
// (2 x AMD EPYC, 2026-12-07, medians of 7 runs, user + system CPU s, minor page faults): igea 1.43
// -> 1.31 (16.8k -> 1.1k faults), nefertiti 0.49 -> 0.45, beast 0.35 -> 0.34, stanford_bunny 0.54
// -> 0.54, menger_sponge3 (3 runs) 11.5 -> 10.3; peak memory igea 198 -> 162 MB. The one lock did
// not cost: igea with --threads 8 on the 2 cores, 1.48 -> 1.24 s wall (medians of 5).
void tune_allocator() {
#if defined(__GLIBC__)
    mallopt(M_ARENA_MAX, 1);
    mallopt(M_MMAP_THRESHOLD, 32 << 20);
    mallopt(M_TRIM_THRESHOLD, 512 << 20);
    heap_on_huge_pages();
#endif
}

bool wants_rerun(std::uintmax_t input_bytes, std::string_view thp_enabled, const char* tunables) {
    if (input_bytes < kRerunFromBytes) return false;
    if (thp_enabled.find("[madvise]") == std::string_view::npos) return false;
    const std::string_view name = kHugeTunable.substr(0, kHugeTunable.find('='));
    return !tunables || std::string_view(tunables).find(name) == std::string_view::npos;
}

std::string with_huge_tunable(const char* tunables) {
    if (!tunables || !*tunables) return std::string(kHugeTunable);
    return std::string(tunables) + ":" + std::string(kHugeTunable);
}

void rerun_on_huge_pages(const std::vector<std::string>& inputs, char** argv) {
#if defined(__GLIBC__)
    if (!kMayRerun) return;
    std::uintmax_t bytes = 0;
    for (const std::string& input : inputs) {
        std::error_code ec;
        const std::uintmax_t size = std::filesystem::file_size(input, ec);
        if (!ec) bytes += size;  // one that cannot be read: the command says what is wrong
    }
    const char* env = std::getenv("GLIBC_TUNABLES");
    if (!wants_rerun(bytes, read_thp_mode(), env)) return;
    const std::optional<std::string> before = env ? std::optional<std::string>(env) : std::nullopt;
    if (setenv("GLIBC_TUNABLES", with_huge_tunable(env).c_str(), 1) != 0) return;
    execv("/proc/self/exe", argv);
    // Not run again: this run goes on as it is, without the tunable in what it starts (OpenSCAD,
    // the slicers).
    if (before) setenv("GLIBC_TUNABLES", before->c_str(), 1);
    else unsetenv("GLIBC_TUNABLES");
#endif
}

}  // namespace cs

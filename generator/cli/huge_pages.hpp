// The process's memory on transparent huge pages (2 MB), where the kernel leaves that to each
// process (its mode `[madvise]`). Each 4 KB page first touched costs a page fault, and on some
// virtual machines a dear one: on the bench machine of 2026-12-06 (2 x AMD EPYC) the 5M-triangle
// scan spent 28.7 of its 75.9 s wall in the kernel (bench/results/scan_5m.md).
//
// Two steps, both process settings, hence in the CLI:
//   - tune_allocator(), first thing in main: every thread allocates from the main heap, glibc keeps
//     buffers up to 32 MB on it and freed memory up to 512 MB, and its first 256 MB take huge
//     pages. Enough for a model of up to a few hundred thousand triangles.
//   - rerun_on_huge_pages(inputs, argv), once the command line is parsed: larger inputs run the
//     whole process again with glibc's own tunable `glibc.malloc.hugetlb=1`, which puts every
//     allocation on huge pages (the buffers over 32 MB, which glibc maps apart from its heap, and
//     the heap past its first 256 MB) and which only the environment of a new process can set.
//
// Example:
//   int main(int argc, char** argv) {
//       cs::tune_allocator();
//       ... parse ...
//       cs::rerun_on_huge_pages({input_path}, argv);  // returns only where it does not run again
//   }
#pragma once

#include <cstdint>  // and with it the C library's __GLIBC__
#include <string>
#include <string_view>
#include <vector>

namespace cs {

// Inputs from this size (bytes of the files a command reads, together) run again with the tunable. On the bench machine
// (2026-12-07, wall s without -> with it, armadillo cut finer, benchmark scale): 5.2M triangles
// (260 MB) 54.4 -> 26.6, 1.3M (65 MB) 9.9 -> 6.2, 470k (23 MB) 2.4 -> 2.2; igea (13 MB) and
// nefertiti (5 MB) the same either way, as the heap's first 256 MB take huge pages already.
// Running again costs what starting does (about 15 ms): under 1 % from here on, even for an
// ASCII STL (about 130k triangles at this size).
constexpr std::uintmax_t kRerunFromBytes = std::uintmax_t{32} << 20;

// Whether this build may run again at all: glibc's, without sanitizers (whose allocator is their
// own).
#if defined(__GLIBC__) && !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__)
#if defined(__has_feature)
#if !__has_feature(address_sanitizer) && !__has_feature(thread_sanitizer) && !__has_feature(memory_sanitizer)
#define CS_MAY_RERUN 1
#endif
#else
#define CS_MAY_RERUN 1
#endif
#endif
#if defined(CS_MAY_RERUN)
constexpr bool kMayRerun = true;
#else
constexpr bool kMayRerun = false;
#endif
#undef CS_MAY_RERUN

// glibc's tunable that puts every allocation on huge pages.
constexpr std::string_view kHugeTunable = "glibc.malloc.hugetlb=1";

// glibc's allocator settings for this process (above). Does nothing outside glibc.
void tune_allocator();

// Whether an input of `input_bytes` should run again with the tunable, where the kernel's mode
// (the text of /sys/kernel/mm/transparent_hugepage/enabled, "" where unreadable) is `thp_enabled`
// and the environment's GLIBC_TUNABLES is `tunables` (nullptr where unset). Not where the kernel
// puts every process on huge pages already (`[always]`) or none (`[never]`), and not where the
// environment names the tunable already, whatever its value (a user's choice, and how a process
// run again knows it was).
bool wants_rerun(std::uintmax_t input_bytes, std::string_view thp_enabled, const char* tunables);

// GLIBC_TUNABLES with kHugeTunable added to what it held (nullptr: unset).
std::string with_huge_tunable(const char* tunables);

// Runs this program again (/proc/self/exe, the same arguments) with kHugeTunable where wants_rerun
// says so for the files `inputs` together (those that cannot be read count nothing) and this
// process; returns where it does not, or cannot (any failure leaves the run as it is: the tunable
// only saves time). Does nothing where kMayRerun is false. Call it before the command prints or
// writes anything.
void rerun_on_huge_pages(const std::vector<std::string>& inputs, char** argv);

}  // namespace cs

// clever-support command line: parses the words (cli/command_line.hpp) and runs the one command
// they choose: generate (the default, cli/grow.hpp), regrow, check, render, apply, presets, view.
// Every error any of them throws becomes a message and an exit code in one place (cli/exit_code.hpp).
#include <CLI/CLI.hpp>
#include <exception>
#if defined(__GLIBC__)  // defined by the C library's headers above
#include <malloc.h>
#include <sys/mman.h>
#include <unistd.h>
#endif
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "cli/command_line.hpp"
#include "cli/exit_code.hpp"
#include "core/errors.hpp"

namespace {

using namespace cs;

int run_command(const CommandLine& cl) {
    if (cl.presets_cmd->parsed()) return cmd_presets();
    if (cl.render_cmd->parsed()) return cmd_render(cl.render);
    if (cl.apply_cmd->parsed()) return cmd_apply(cl.apply);
    if (cl.check_cmd->parsed()) return cmd_check(cl.check);
    if (cl.regrow_cmd->parsed()) return cmd_regrow(cl.regrow, cl.run);
    if (cl.view_cmd->parsed()) return run_view_command(cl.view);
    return cmd_generate(cl.generate, cl.run);
}

// The heap on transparent huge pages. Each 4 KB page the heap first touches costs a page fault, and
// on some virtual machines a dear one: igea (270k triangles) took 39.5k faults and 0.35 of its
// 2.1 CPU-s in the kernel on the bench machine (2 x AMD EPYC, 2026-12-06). The first kHugeHeap of
// the main heap, reserved at once (address space only) and marked MADV_HUGEPAGE, takes 2 MB pages:
// igea 5.9k faults and 1.6 CPU-s, the same as glibc's own glibc.malloc.hugetlb=1 tunable, which
// only the environment of a new process can set. Where the kernel's transparent huge pages are off,
// the advice does nothing.
// Under M_TRIM_THRESHOLD (tune_allocator), so glibc keeps it when it is free.
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

// One run builds and drops many buffers of megabytes (the mesh, its index, the 3MF XML and its
// deflated package, the STLs). glibc maps each one above 128 KB fresh from the kernel and unmaps it
// on free, so every run pays the page faults again, and it hands the top of the heap back as soon
// as 128 KB are free there. Keeping buffers up to 32 MB on the heap and freed memory up to 512 MB:
// igea (270k triangles) 2.5 -> 2.0 CPU-s, peak memory +9 %. A process setting, hence here in main.
// Then the heap on huge pages.
void tune_allocator() {
#if defined(__GLIBC__)
    mallopt(M_MMAP_THRESHOLD, 32 << 20);
    mallopt(M_TRIM_THRESHOLD, 512 << 20);
    heap_on_huge_pages();
#endif
}

}  // namespace

int main(int argc, char** argv) {
    tune_allocator();
    CLI::App app{"clever-support: tree supports for FDM prints, as printable STL and parametric OpenSCAD.\n"
                 "Examples:\n"
                 "  clever-support model.stl                       # supports into out/model/\n"
                 "  clever-support --fit 80 --render scan.obj      # scale to 80 mm, render the SCAD too\n"
                 "  clever-support --preset replicator2-pla --orient keep part.stl\n"
                 "  clever-support check out/m/                     # the run's meshes, settings and blockers\n"
                 "  clever-support apply out/m/m.scad -D k=0.003    # a tweak into the STLs and 3MFs\n"
                 "  clever-support --compare prusa part.stl         # and PrusaSlicer's own supports beside ours\n"
                 "  clever-support part.scad -D width=30 --support-blocker 0,0,0,10,10,20\n"
                 "  clever-support regrow out/m/m.scad              # after editing it\n",
                 "clever-support"};
    CommandLine cl;
    add_commands(app, cl);
    try {
        reject_unknown_subcommand(app, argc, argv);
        try {
            app.parse(argc, argv);
        } catch (const CLI::ExtrasError&) {
            throw UsageError(unexpected_arguments(app));
        }
        return run_command(cl);
    } catch (const CLI::Success& e) {  // --help, --version
        return app.exit(e);
    } catch (...) {
        return exit_code_for(std::current_exception());
    }
}

#include "cli/exit_code.hpp"

#include <CLI/CLI.hpp>
#include <cstdio>
#include <new>
#include <string>

#include "core/errors.hpp"

namespace cs {
namespace {

void print_error(const std::string& msg) { std::fprintf(stderr, "clever-support: error: %s\n", msg.c_str()); }

}  // namespace

int exit_code_for(const std::exception_ptr& error) {
    try {
        std::rethrow_exception(error);
    } catch (const CLI::ParseError& e) {
        print_error(std::string(e.what()) + ". Run `clever-support --help` for usage.");
        return kExitUsage;
    } catch (const ParameterError& e) {
        print_error(std::string(e.what()) + ".");
        return kExitUsage;
    } catch (const UsageError& e) {
        print_error(e.what());
        return kExitUsage;
    } catch (const InputError& e) {
        print_error(e.what());
        return kExitBadInput;
    } catch (const ExternalToolError& e) {
        print_error(e.what());
        if (!e.log.empty()) std::fprintf(stderr, "%s", e.log.c_str());
        return kExitRenderFailed;
    } catch (const OutputError& e) {
        print_error(e.what());
        return kExitOutputFailed;
    } catch (const std::bad_alloc&) {
        print_error("out of memory. Try a larger --sampling or a smaller model.");
        return kExitInternal;
    } catch (const std::exception& e) {
        print_error(std::string("internal error: ") + e.what() + ". Please report this with the input file.");
        return kExitInternal;
    }
}

}  // namespace cs

// clever-support-view: the page's server of `clever-support view`, an executable of its own so that
// only `view` loads the web server's libraries (view/view_cli.hpp says why). clever-support starts
// it by becoming it (execv), with the folder, its own path (for regrow) and the page's folder.
#include <cstdio>
#include <exception>

#include "cli/exit_code.hpp"
#include "core/errors.hpp"
#include "view/view_cli.hpp"
#include "view/view_server.hpp"

int main(int argc, char** argv) {
    const auto options = cs::view_options_from_args(argc, argv);
    if (!options) {
        std::fprintf(stderr, "clever-support-view: started by `clever-support view FOLDER`; run that instead\n");
        return cs::kExitUsage;
    }
    try {
        cs::serve_view(*options);
        return cs::kExitOk;
    } catch (...) {
        return cs::exit_code_for(std::current_exception());
    }
}

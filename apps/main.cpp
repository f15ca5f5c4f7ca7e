// `lobe`: the command line of the Lobe renderer. Errors in input (files, scenes, parameters) are
// thrown once as lobe::Error and reported here as one line with a non-zero exit.
#include "apps/commands.h"
#include "core/error.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>

int main(int argc, char** argv) {
    CLI::App app{"Lobe: renders medical volume data in which every object has its own BRDF.\n"
                 "Run 'lobe COMMAND --help' for the options of one command."};
    app.require_subcommand(1);
    app.set_version_flag("--version", "lobe 0.1.0");
    lobe::registerBrdfCommand(app);
    lobe::registerGalleryCommands(app);
    lobe::registerRenderCommand(app);
    lobe::registerDemoCommand(app);
    lobe::registerOverlapCommand(app);
    lobe::registerSeparationCommand(app);
    lobe::registerAssignCommand(app);
    lobe::registerInfoCommand(app);
    lobe::registerConvertCommand(app);

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
        // A bad command line is an input error like any other: one line, exit 1.
        std::fprintf(stderr, "lobe: error: %s (see 'lobe COMMAND --help')\n", e.what());
        return 1;
    } catch (const lobe::Error& e) {
        std::fprintf(stderr, "lobe: error: %s\n", e.what());
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "lobe: internal error: %s\n", e.what());
        return 2;
    }
    return 0;
}

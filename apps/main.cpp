// `lobe`: the command line of the Lobe renderer. Errors in input (files, scenes, parameters) are
// thrown once as lobe::Error and reported here as one line with a non-zero exit.
#include "apps/commands.h"
#include "cluster/cluster.h"
#include "core/error.h"
#include "core/interrupt.h"
#include "core/memory.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>
#include <filesystem>
#include <new>
#include <string>

namespace {

// Under mpirun: an error one process found alone ends the whole run (MPI_Abort), so that no
// process waits for it; the message names the rank. Errors every process knows of
// (cluster::CollectiveError) end each process normally, printed once.
int fail(int code, const char* kind, const std::string& message) {
    if (!lobe::cluster::distributed()) {
        std::fprintf(stderr, "lobe: %s: %s\n", kind, message.c_str());
        return code;
    }
    std::fprintf(stderr, "lobe: %s on rank %d of %d: %s\n", kind, lobe::cluster::rank(),
                 lobe::cluster::size(), message.c_str());
    std::fflush(stderr);
    lobe::cluster::abort(code);
}

int run(int argc, char** argv) {
    CLI::App app{
        "Lobe: renders medical volume data in which every object has its own BRDF.\n"
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
    lobe::registerCostCommand(app);
    lobe::registerInfoCommand(app);
    lobe::registerConvertCommand(app);
    lobe::registerStudyCommand(app);

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
        // A bad command line is an input error like any other: one line, exit 1 (every
        // process of an mpirun finds the same, so the first prints it).
        if (lobe::cluster::isRoot())
            std::fprintf(stderr, "lobe: error: %s (see 'lobe COMMAND --help')\n", e.what());
        return 1;
    } catch (const lobe::cluster::CollectiveError& e) {
        if (e.reportHere()) std::fprintf(stderr, "lobe: error: %s\n", e.what());
        return 1;
    } catch (const lobe::Error& e) {
        return fail(1, "error", e.what());
    } catch (const std::bad_alloc&) {
        // An allocation beyond what the process may use (ulimit -v, a cgroup's memory.max as
        // Slurm's --mem sets): say so, with the limit, rather than "std::bad_alloc".
        return fail(1, "error",
                    lobe::outOfMemoryText() +
                        "; use a smaller image, fewer samples "
                        "per band (--band-rows), or more memory");
    } catch (const std::filesystem::filesystem_error& e) {
        // A path the system refuses (a symbolic link loop, a permission) wherever it was met:
        // the path and the reason, an input error like any other.
        return fail(1, "error", "'" + e.path1().string() + "': " + e.code().message());
    } catch (const std::exception& e) {
        return fail(2, "internal error", e.what());
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    lobe::installInterruptCleanup();
    try {
        lobe::cluster::start(&argc, &argv);
    } catch (const lobe::Error& e) {
        std::fprintf(stderr, "lobe: error: %s\n", e.what());
        return 1;
    }
    const int code = run(argc, argv);
    lobe::cluster::stop();
    return code;
}

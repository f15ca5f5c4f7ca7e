// `lobe convert IN OUT.vdb [options]`: loads any supported volume (raw with a layout, NIfTI,
// NRRD .nhdr, .vdb) and writes it as an OpenVDB float grid with Lobe's metadata, so later runs
// load it without options. The output is written to a temporary name and renamed: on any error
// nothing is written.
#include "apps/commands.h"
#include "volume/volume_summary.h"

#include <CLI/CLI.hpp>

#include <memory>
#include <string>

namespace lobe {

// Shared with `lobe info`, defined in cmd_info.cpp.
void addVolumeOptions(CLI::App& cmd, VolumeOptionText& text);
void printVolumeSummary(const VolumeSummary& summary);

void registerConvertCommand(CLI::App& app) {
    struct Options {
        std::string in, out, name;
        VolumeOptionText text;
    };
    auto options = std::make_shared<Options>();
    CLI::App* cmd = app.add_subcommand(
        "convert", "Convert a volume (.nii, .nii.gz, .nhdr, .vdb, raw with --dims --type "
                   "--endian --spacing) to an OpenVDB .vdb file");
    cmd->add_option("IN", options->in, "the input volume")->required();
    cmd->add_option("OUT", options->out, "the output .vdb file")->required();
    addVolumeOptions(*cmd, options->text);
    cmd->add_option("--name", options->name, "name of the written grid (default 'density')");
    cmd->add_option("--input-grid", options->text.gridName, ".vdb input: the grid to read");
    cmd->callback([options] {
        const VolumeSummary s = convertVolume(options->in, options->out,
                                              parseLoadOptions(options->text), options->name);
        printVolumeSummary(s);
    });
}

}  // namespace lobe

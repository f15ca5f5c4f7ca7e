// `lobe convert IN... OUT.vdb [options]`: loads any supported volume (raw with a layout, NIfTI,
// NRRD .nhdr, .vdb, a DICOM folder or the files of one series) and writes it as an OpenVDB float
// grid with Lobe's metadata, so later runs load it without options. The output is written to a
// temporary name and renamed: on any error nothing is written.
#include "apps/commands.h"
#include "core/error.h"
#include "volume/volume_summary.h"

#include <CLI/CLI.hpp>

#include <memory>
#include <string>
#include <vector>

namespace lobe {

// Shared with `lobe info`, defined in cmd_info.cpp.
void addVolumeOptions(CLI::App& cmd, VolumeOptionText& text);
void printVolumeSummary(const VolumeSummary& summary);

void registerConvertCommand(CLI::App& app) {
    struct Options {
        std::vector<std::string> in;
        std::string out, name;
        VolumeOptionText text;
    };
    auto options = std::make_shared<Options>();
    CLI::App* cmd = app.add_subcommand(
        "convert",
        "Convert a volume (.nii, .nii.gz, .nhdr, .vdb, a DICOM series as a folder "
        "or its files, raw with --dims --type --endian --spacing) to an OpenVDB .vdb "
        "file");
    // One list: CLI11 gives a vector positional every word, so OUT is taken from its end.
    cmd->add_option("IN... OUT", options->in,
                    "the input volume (or a DICOM folder, or the DICOM files of one series), then "
                    "the output .vdb file")
        ->required();
    addVolumeOptions(*cmd, options->text);
    cmd->add_option("--name", options->name, "name of the written grid (default 'density')");
    cmd->add_option("--input-grid", options->text.gridName, ".vdb input: the grid to read");
    cmd->callback([options] {
        if (options->in.size() < 2)
            throw Error("convert needs an input and an output: lobe convert IN... OUT.vdb");
        options->out = options->in.back();
        options->in.pop_back();
        const VolumeSummary s = convertVolume(options->in, options->out,
                                              parseLoadOptions(options->text), options->name);
        printVolumeSummary(s);
    });
}

}  // namespace lobe

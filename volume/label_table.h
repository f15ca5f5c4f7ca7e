// Label tables: the names and colours of the labels of a segmentation or atlas (a label map, whose
// voxels hold whole-number labels), read from the formats the tools that make them write. No
// OpenVDB here. The formats (detected from the first data line; '#' starts a comment line):
// - FreeSurfer's colour table (FreeSurferColorLUT.txt, the `ctab` files of `mri_segstats
//   --ctab`): "index name R G B A" per line, R G B in 0–255; the fourth number (0 throughout
//   FreeSurferColorLUT.txt) is read and not used: objects are opaque unless the scene says.
// - ITK-SNAP label descriptions (Segmentation › Export label descriptions):
//   "IDX R G B A VIS MSH "LABEL"", R G B in 0–255, A the opacity 0–1, the name in double quotes.
// - MRIcron's atlas text file beside the atlas (aal.nii.txt): "index name" or "index name code"
//   (the third number is the atlas's own code, e.g. AAL's 2001 for Precentral_L, kept unread),
//   and its colour file (aal.nii.lut): 768 bytes, the red values of the indices 0–255, then the
//   green, then the blue (planar, as ImageJ's binary LUTs and MRIcron's LoadColorScheme read it).
// - A table given in the scene (render/scene_file.cpp builds it directly).
// Colours are kept as the files give them: sRGB-encoded bytes 0–255.
#pragma once

#include <array>
#include <map>
#include <string>
#include <vector>

namespace lobe {

struct LabelEntry {
    int id = 0;
    std::string name;
    bool hasColour = false;
    std::array<int, 3> rgb{255, 255, 255};  // sRGB-encoded, 0–255
    double opacity = 1.0;                   // ITK-SNAP's A (0–1); 1 otherwise
};

struct LabelTable {
    std::string source;  // the file(s) it was read from, for messages ("" when none)
    std::string format;  // "freesurfer", "itksnap", "mricron", "scene"
    std::map<int, LabelEntry> entries;

    bool empty() const { return entries.empty(); }
    const LabelEntry* find(int id) const;
    // The label of `name` (exact, then case-insensitive), or -1.
    int idOf(const std::string& name) const;
    // "did you mean …": the nearest names by edit distance (at most 3), for messages.
    std::vector<std::string> nearestNames(const std::string& name) const;
};

// A text table in any of the three formats above (the format detected from its first data
// line), or an MRIcron .lut (then the .txt of the same stem beside it, when there is one, gives
// the names). Throws lobe::Error naming the file and line for anything it cannot read.
LabelTable readLabelTable(const std::string& path);
// MRIcron's pair: names from `txtPath` ("" for none), colours from `lutPath` ("" for none).
LabelTable readMricronTable(const std::string& txtPath, const std::string& lutPath);
// The MRIcron table that sits beside a label map: MAP.txt and/or MAP.lut where MAP is the map's
// path without a trailing ".gz" (aal.nii.gz → aal.nii.txt, aal.nii.lut). Empty when neither exists.
LabelTable tableBeside(const std::string& mapPath);

}  // namespace lobe

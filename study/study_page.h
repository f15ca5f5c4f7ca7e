// `lobe study SCENES… --out DIR` (docs/study.md): the stimuli rendered through `lobe render`'s
// batch (batch/batch.h), the trial list (DIR/study.json) and the experiment page
// (DIR/index.html: the template study/study_page.html, compiled in, with the study in it).
#pragma once

#include "render/scene_overrides.h"

#include <cstdint>
#include <string>
#include <vector>

namespace lobe {

struct StudyRequest {
    std::vector<std::string> scenes;  // one condition per scene file
    std::string outDir;
    std::string task = "pair";  // pair, which-object or both
    int orbit = 0;              // > 0: each condition an N-frame turntable (pairs animate it)
    int repeats = 2;            // each pair of conditions shown this many times
    int checks = 2;             // attention checks per task
    uint64_t seed = 1;          // attention checks' draws; the page mixes it with the participant
    std::string question = "In which image can you tell the structures apart more easily?";
    SceneOverrides overrides;
    bool quiet = false;
};

// Renders the stimuli into DIR/stimuli, writes DIR/study.json and DIR/index.html. Throws
// lobe::Error (nothing written over: DIR must not hold a study already).
void buildStudy(const StudyRequest& request);

// The page template (study/study_page.html, embedded at build time).
const char* studyPageTemplate();
// The page for a study.json text: the template with the study in place of its marker (with
// "</" written "<\/" so no text of the study can end the script).
std::string studyPage(const std::string& studyJson);

// writeTextFileAtomic: core/temporary_file.h.

}  // namespace lobe

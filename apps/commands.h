// Each `lobe` subcommand lives in its own cmd_<name>.cpp and registers itself on the app here.
// main.cpp lists them; CLI::App is only forward-declared so this header stays cheap.
#pragma once

namespace CLI {
class App;
}

namespace lobe {

void registerBrdfCommand(CLI::App& app);
void registerGalleryCommands(CLI::App& app);
void registerRenderCommand(CLI::App& app);
void registerDemoCommand(CLI::App& app);
void registerOverlapCommand(CLI::App& app);
void registerInfoCommand(CLI::App& app);
void registerConvertCommand(CLI::App& app);
void registerSeparationCommand(CLI::App& app);
void registerAssignCommand(CLI::App& app);
void registerCostCommand(CLI::App& app);
void registerStudyCommand(CLI::App& app);

}  // namespace lobe

// SPDX-License-Identifier: Apache-2.0
/// @file commands.h
/// @brief The `kizamu` subcommands: each registers its options on a CLI11 app and runs.
#pragma once

#include <string>

namespace CLI {
class App;
}

namespace kizamu::mesh {
struct UntangleReport;
}

namespace kizamu::app {

/// True when `path` names an ADF file (.kza, any case).
bool isAdfPath(const std::string& path);

/// Prints what an export's untangling removed (nothing when it found nothing), and warns on
/// stderr when contacts remain.
void printUntangled(const mesh::UntangleReport& r);

/// Registers `info`: summary of a .kza file.
void addInfoCommand(CLI::App& app);
/// Registers `generate`: builds the test part (or a primitive) and writes a .kza file.
void addGenerateCommand(CLI::App& app);
/// Registers `convert`: mesh formats, and mesh to ADF.
void addConvertCommand(CLI::App& app);
/// Registers `run`: replays a stroke script.
void addRunCommand(CLI::App& app);
/// Registers `render`: a picture of an ADF, a session or a mesh, off screen. Defined only where
/// the renderer is built (KIZAMU_HAVE_RENDER, from KIZAMU_BUILD_RENDER).
void addRenderCommand(CLI::App& app);
/// Registers `sculpt`: the sculpting window. Defined only where the renderer is built.
void addSculptCommand(CLI::App& app);
/// Registers `live`: a tool trajectory through the live engine.
void addLiveCommand(CLI::App& app);
/// Registers `devices`: the haptic devices found, and the simulated stylus.
void addDevicesCommand(CLI::App& app);
/// Registers `bench` with its areas (`bench adf`, `bench mesh`, `bench edit`). Defined only
/// where the benchmark library is built (KIZAMU_HAVE_BENCH, from KIZAMU_BUILD_BENCH).
void addBenchCommand(CLI::App& app);

}  // namespace kizamu::app

// What the Viewer writes when asked: the scene as it is now (Ctrl+S, File > Save scene) and
// screenshots (F12, a script's screenshot step). Each says where it wrote on stdout and in the
// status line, or what went wrong on stderr and in the status line.
#include "ui/Viewer.h"

#include "base/Png.h"
#include "engine/scene/SceneSave.h"

#include <chrono>
#include <cstdio>

namespace orbis::ui {

bool Viewer::saveScene() {
    const std::filesystem::path to = panels_.savePath();
    return reportWritten(scene::saveScene(*scene_, to), to);
}

bool Viewer::writeScreenshot(const render::FrameResult& frame, std::filesystem::path file) {
    if (file.empty()) {
        const auto stamp = std::chrono::duration_cast<std::chrono::seconds>(
                               std::chrono::system_clock::now().time_since_epoch()).count();
        file = options_.screenshotFolder / ("orbis-" + std::to_string(stamp) + ".png");
    }
    ImageRgba8 image{renderer_->width(), renderer_->height(), renderer_->readPixels(frame)};
    return reportWritten(writePng(file, image), file);
}

bool Viewer::reportWritten(const Result<void>& written, const std::filesystem::path& file) {
    if (!written) {
        readout_.message = written.message();
        printError(written.message());
        return false;
    }
    readout_.message = "saved " + file.filename().string();
    std::printf("wrote %s\n", file.string().c_str());
    std::fflush(stdout);
    return true;
}

}  // namespace orbis::ui

// SPDX-License-Identifier: Apache-2.0
/// @file file_browser.cpp
/// @brief FileBrowser: the listing, the path field's verbs, and its ImGui window.
#include "ui/file_browser.h"

#include <imgui.h>
#include <imgui_stdlib.h>

#include <algorithm>
#include <filesystem>
#include <system_error>
#include <utility>

namespace kizamu::ui {

namespace {

namespace fs = std::filesystem;

/// The path field's text to put in place of what the field holds, when `replace`.
struct FieldText {
    bool replace = false;
    std::string text;
};

int replaceFieldText(ImGuiInputTextCallbackData* data) {
    auto* field = static_cast<FieldText*>(data->UserData);
    if (!field->replace) return 0;
    data->DeleteChars(0, data->BufTextLen);
    data->InsertChars(0, field->text.c_str());
    field->replace = false;
    return 0;
}

const char* titleOf(FileBrowserMode mode) {
    switch (mode) {
    case FileBrowserMode::Open: return "Open";
    case FileBrowserMode::SaveAs: return "Save as";
    case FileBrowserMode::Export: return "Export";
    }
    return "";
}

}  // namespace

std::vector<FileEntry> listDirectory(const std::string& dir, const FileBrowserSettings& settings) {
    std::vector<FileEntry> dirs, files;
    std::error_code ec;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        if (name.empty() || name[0] == '.') continue;
        std::error_code statError;
        const std::string path = it->path().string();
        if (it->is_directory(statError)) {
            const bool session = settings.isSession && settings.isSession(path);
            dirs.push_back({name, session ? FileEntry::Kind::Session : FileEntry::Kind::Directory});
        } else if (it->is_regular_file(statError) && (!settings.accepts || settings.accepts(path))) {
            files.push_back({name, FileEntry::Kind::File});
        }
    }
    const auto byName = [](const FileEntry& a, const FileEntry& b) { return a.name < b.name; };
    std::sort(dirs.begin(), dirs.end(), byName);
    std::sort(files.begin(), files.end(), byName);
    dirs.insert(dirs.end(), std::make_move_iterator(files.begin()), std::make_move_iterator(files.end()));
    return dirs;
}

void FileBrowser::open(FileBrowserSettings settings) {
    mSettings = std::move(settings);
    std::error_code ec;
    std::string dir = mSettings.directory.empty() ? fs::current_path(ec).string() : mSettings.directory;
    enter(dir);
    if (!mSettings.path.empty()) mPath = mSettings.path;
    mChosen.reset();
    mOpen = true;
}

void FileBrowser::enter(const std::string& dir) {
    std::error_code ec;
    const fs::path absolute = fs::weakly_canonical(fs::absolute(fs::path(dir), ec), ec);
    mDirectory = absolute.string();
    mEntries = listDirectory(mDirectory, mSettings);
    mPath = (absolute / "").string();  // a trailing separator: typing a name completes the path
    mPathFilledIn = true;
    mPathChanged = true;
    mFocusField = true;
}

void FileBrowser::typeText(std::string_view text) {
    // An absolute path typed over the directory the browser filled in replaces it.
    if (mPathFilledIn && fs::path(text).is_absolute()) mPath.clear();
    mPath.append(text);
    mPathFilledIn = false;
    mPathChanged = true;
}

void FileBrowser::eraseLast() {
    if (mPath.empty()) return;
    std::size_t n = mPath.size() - 1;
    while (n > 0 && (static_cast<unsigned char>(mPath[n]) & 0xC0u) == 0x80u) --n;  // UTF-8 continuation bytes
    mPath.erase(n);
    mPathFilledIn = false;
    mPathChanged = true;
}

void FileBrowser::accept() {
    if (mPath.empty()) return;
    fs::path p(mPath);
    std::error_code ec;
    if (p.is_relative()) p = fs::path(mDirectory) / p;
    const std::string path = p.lexically_normal().string();
    const bool session = mSettings.isSession && mSettings.isSession(path);
    if (mSettings.mode == FileBrowserMode::Open && fs::is_directory(path, ec) && !session) {
        enter(path);
        return;
    }
    std::string chosen = path;
    if (chosen.size() > 1 && chosen.back() == fs::path::preferred_separator) chosen.pop_back();
    choose(std::move(chosen));
}

void FileBrowser::choose(std::string path) {
    mChosen = std::move(path);
    mOpen = false;
}

std::optional<std::string> FileBrowser::takeChosen() { return std::exchange(mChosen, std::nullopt); }

void FileBrowser::draw() {
    if (!mOpen) return;
    const ImGuiViewport* view = ImGui::GetMainViewport();
    ImGui::SetNextWindowPos(ImVec2(view->WorkPos.x + view->WorkSize.x * 0.5f, view->WorkPos.y + view->WorkSize.y * 0.5f),
                            ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
    ImGui::SetNextWindowSize(ImVec2(520, 420), ImGuiCond_Appearing);
    bool keepOpen = true;
    if (!ImGui::Begin(titleOf(mSettings.mode), &keepOpen, ImGuiWindowFlags_NoCollapse)) {
        ImGui::End();
        if (!keepOpen) close();
        return;
    }
    ImGui::TextUnformatted(mDirectory.c_str());
    if (mFocusField) {
        ImGui::SetKeyboardFocusHere();
        mFocusField = false;
    }
    ImGui::SetNextItemWidth(-1.0f);
    // While the field has the keyboard its own copy of the text wins over mPath: a path changed
    // here (typed by a script, an entry clicked) replaces that copy through the callback.
    FieldText replacement{mPathChanged, mPath};
    const bool entered = ImGui::InputText("##path", &mPath, ImGuiInputTextFlags_EnterReturnsTrue | ImGuiInputTextFlags_CallbackAlways,
                                          replaceFieldText, &replacement);
    mPathChanged = false;
    std::optional<std::string> enterDir, choosePath;
    if (ImGui::BeginChild("entries", ImVec2(0, -ImGui::GetFrameHeightWithSpacing()), true)) {
        if (ImGui::Selectable("..", false, ImGuiSelectableFlags_AllowDoubleClick) && ImGui::IsMouseDoubleClicked(0))
            enterDir = fs::path(mDirectory).parent_path().string();
        for (const FileEntry& e : mEntries) {
            const std::string path = (fs::path(mDirectory) / e.name).string();
            const std::string label = e.kind == FileEntry::Kind::Directory ? e.name + "/"
                                      : e.kind == FileEntry::Kind::Session ? e.name + "/  [session]"
                                                                           : e.name;
            if (!ImGui::Selectable(label.c_str(), mPath == path, ImGuiSelectableFlags_AllowDoubleClick)) continue;
            mPath = path;
            mPathFilledIn = true;
            mPathChanged = true;
            if (!ImGui::IsMouseDoubleClicked(0)) continue;
            if (e.kind == FileEntry::Kind::Directory) enterDir = path;
            else choosePath = path;
        }
    }
    ImGui::EndChild();
    if (ImGui::Button("Up")) enterDir = fs::path(mDirectory).parent_path().string();
    ImGui::SameLine();
    const bool clicked = ImGui::Button(titleOf(mSettings.mode));
    ImGui::SameLine();
    if (ImGui::Button("Cancel")) keepOpen = false;
    ImGui::End();
    if (!keepOpen) close();
    else if (enterDir) enter(*enterDir);
    else if (choosePath) choose(*choosePath);
    else if (entered || clicked) accept();
}

}  // namespace kizamu::ui

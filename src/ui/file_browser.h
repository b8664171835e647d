// SPDX-License-Identifier: Apache-2.0
/// @file file_browser.h
/// @brief A small file browser in Dear ImGui for the sculpting window: Open (Ctrl+O), Save As
/// (Ctrl+Shift+S) and Export use the same one.
///
/// It shows one directory: its parent, then its subdirectories and then the files the caller
/// accepts (FileBrowserSettings::accepts), each group sorted by name. A directory that holds a
/// Kizamu session (sculpt::isSessionDir) is marked and chosen like a file rather than entered.
/// An editable path field holds what will be chosen: a click on an entry puts its path there, a
/// double click enters a directory or chooses a file or session, Enter chooses the field (or
/// enters it when it names a plain directory and the mode is Open). The state and its verbs
/// (typeText, accept, ...) are separate from draw(), so an input script types into the field
/// and presses Enter through the same code a person's keyboard reaches.
/// Threading: the UI thread only (draw() between ImGui's NewFrame and Render). One per window;
/// the listing is read from disk when the directory changes, never per frame.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace kizamu::ui {

/// What the chosen path is for; it names the window and its button.
enum class FileBrowserMode { Open, SaveAs, Export };

/// One entry of a listed directory.
struct FileEntry {
    enum class Kind { Directory, Session, File };
    std::string name;  ///< the file name, without the directory
    Kind kind = Kind::File;
    bool operator==(const FileEntry&) const = default;
};

struct FileBrowserSettings {
    FileBrowserMode mode = FileBrowserMode::Open;
    std::string directory;  ///< where it starts; empty: the current working directory
    std::string path;       ///< the path field's first text; empty: the directory
    /// Which regular files are listed (by path); empty: all of them.
    std::function<bool(const std::string&)> accepts;
    /// Which directories are sessions (by path; sculpt::isSessionDir); empty: none.
    std::function<bool(const std::string&)> isSession;
};

/// Lists `dir`: subdirectories first (those `settings.isSession` names marked Kind::Session),
/// then the regular files `settings.accepts` takes; each group sorted by name; hidden entries (a
/// leading '.') left out. An unreadable directory lists nothing.
/// Complexity: O(n log n) in the directory's entries, one stat per entry plus the predicates.
/// Threading: any thread. Memory: allocates the result.
std::vector<FileEntry> listDirectory(const std::string& dir, const FileBrowserSettings& settings);

/// The browser: closed until open(), closed again once a path is chosen or it is cancelled.
/// Owned by the window's application; not thread-safe.
class FileBrowser {
public:
    void open(FileBrowserSettings settings);
    void close() { mOpen = false; }
    bool isOpen() const { return mOpen; }
    FileBrowserMode mode() const { return mSettings.mode; }
    const std::string& directory() const { return mDirectory; }
    const std::vector<FileEntry>& entries() const { return mEntries; }
    const std::string& path() const { return mPath; }

    /// Lists `dir` and puts it in the path field.
    void enter(const std::string& dir);
    /// Appends `text` to the path field (what typing does); an absolute path typed over what the
    /// browser filled in (a directory entered, an entry clicked) replaces it.
    void typeText(std::string_view text);
    /// Removes the path field's last character (UTF-8 aware).
    void eraseLast();
    /// Enter: a plain directory in Open mode is entered, anything else is chosen (empty: nothing).
    void accept();
    /// The path chosen since the last call, once; the browser has closed by then.
    std::optional<std::string> takeChosen();

    /// Draws the browser's window when open (ImGui calls; nothing when closed).
    void draw();

private:
    void choose(std::string path);

    FileBrowserSettings mSettings;
    bool mOpen = false;
    bool mFocusField = false;  ///< the path field takes the keyboard (and reloads its text) on the next draw
    bool mPathFilledIn = false;  ///< the path field holds what the browser put there, untouched since
    bool mPathChanged = false;   ///< mPath changed outside the field since its last draw
    std::string mDirectory;
    std::vector<FileEntry> mEntries;
    std::string mPath;
    std::optional<std::string> mChosen;
};

}  // namespace kizamu::ui

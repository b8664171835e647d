// SPDX-License-Identifier: Apache-2.0
// The file browser's model (file_browser.h), without a window: the listing (directories first,
// sessions marked, files filtered, each group sorted, hidden entries left out) and the path
// field's verbs (typing, erasing, Enter entering a directory or choosing a path).
#include "ui/file_browser.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>

namespace kizamu {
namespace {

namespace fs = std::filesystem;
using ui::FileEntry;

struct Tree {
    fs::path root = fs::temp_directory_path() / ("kizamu-browser-" + std::to_string(::getpid()));
    Tree() {
        fs::remove_all(root);
        for (const char* d : {"b-dir", "a-session", ".hidden-dir"}) fs::create_directories(root / d);
        std::ofstream(root / "a-session" / "journal.jsonl") << "{}\n";
        for (const char* f : {"z.obj", "m.STL", "notes.txt", ".hidden.obj"}) std::ofstream(root / f) << "x\n";
    }
    ~Tree() { fs::remove_all(root); }
};

ui::FileBrowserSettings meshSettings(ui::FileBrowserMode mode = ui::FileBrowserMode::Open) {
    ui::FileBrowserSettings s;
    s.mode = mode;
    s.accepts = [](const std::string& p) {
        const std::string e = fs::path(p).extension().string();
        return e == ".obj" || e == ".STL";
    };
    s.isSession = [](const std::string& p) { return fs::exists(fs::path(p) / "journal.jsonl"); };
    return s;
}

TEST(FileBrowser, ListsDirectoriesFirstMarksSessionsAndFiltersFiles) {
    const Tree t;
    const std::vector<FileEntry> expected = {{"a-session", FileEntry::Kind::Session},
                                             {"b-dir", FileEntry::Kind::Directory},
                                             {"m.STL", FileEntry::Kind::File},
                                             {"z.obj", FileEntry::Kind::File}};
    EXPECT_EQ(ui::listDirectory(t.root.string(), meshSettings()), expected);
    EXPECT_TRUE(ui::listDirectory((t.root / "missing").string(), meshSettings()).empty());
}

TEST(FileBrowser, EnterEntersAPlainDirectoryAndChoosesSessionsAndFiles) {
    const Tree t;
    ui::FileBrowser b;
    ui::FileBrowserSettings s = meshSettings();
    s.directory = t.root.string();
    b.open(s);
    ASSERT_TRUE(b.isOpen());
    EXPECT_EQ(b.entries().size(), 4u);
    b.typeText("b-dir");
    b.accept();
    EXPECT_TRUE(b.isOpen()) << "a plain directory is entered";
    EXPECT_EQ(fs::path(b.directory()), t.root / "b-dir");
    EXPECT_FALSE(b.takeChosen().has_value());
    b.typeText("../a-sessioX");
    b.eraseLast();
    b.typeText("n");
    b.accept();
    EXPECT_FALSE(b.isOpen());
    EXPECT_EQ(b.takeChosen(), (t.root / "a-session").string()) << "a session is chosen, not entered";
    EXPECT_FALSE(b.takeChosen().has_value()) << "once";

    b.open(s);
    b.typeText((t.root / "z.obj").string());
    b.accept();
    EXPECT_EQ(b.takeChosen(), (t.root / "z.obj").string()) << "an absolute path typed replaces the directory filled in";

    s.mode = ui::FileBrowserMode::SaveAs;
    b.open(s);
    b.typeText("b-dir");
    b.accept();
    EXPECT_EQ(b.takeChosen(), (t.root / "b-dir").string()) << "Save As chooses a directory";
}

}  // namespace
}  // namespace kizamu

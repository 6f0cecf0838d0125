// tests/apps/docs_links_test.cpp — the documentation cites only what the repository carries.
//
// Scans README.md and every docs/**/*.md for (a) markdown link targets `](target)` that are not
// URLs or anchors, resolved against the file's own directory, and (b) repository paths written
// in the text — words, inside or outside backticks and code blocks, that start with the name of a
// top-level directory of the repository (`docs/…`, `scenes/…`, `tests/…`, optionally after
// `./`) and name a file (an extension) or a directory (a trailing '/') — resolved against the
// repository root; each must exist. Words with placeholders or wildcards (`<`, `*`, `…`, `{`,
// `$`) are not paths and are skipped. No file may cite the outside
// of the repository (`../shared`, `/work/`).
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

const fs::path kRoot = CERTRAY_SOURCE_DIR;

std::string read(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

/// README.md and docs/**/*.md, as paths relative to the root.
std::vector<fs::path> markdown_files() {
    std::vector<fs::path> files{"README.md"};
    for (const auto& e : fs::recursive_directory_iterator(kRoot / "docs")) {
        if (e.is_regular_file() && e.path().extension() == ".md") {
            files.push_back(fs::relative(e.path(), kRoot));
        }
    }
    return files;
}

/// The top-level directories a cited path may start with (not .git, the build trees or out/).
std::set<std::string> top_dirs() {
    std::set<std::string> dirs;
    for (const auto& e : fs::directory_iterator(kRoot)) {
        const std::string name = e.path().filename().string();
        if (!e.is_directory() || name == ".git" || name == "out" || name.rfind("build", 0) == 0) {
            continue;
        }
        dirs.insert(name);
    }
    return dirs;
}

/// The line (1-based) of byte offset `pos` in `text`.
int line_of(const std::string& text, std::size_t pos) {
    return 1 + static_cast<int>(std::count(text.begin(), text.begin() + pos, '\n'));
}

TEST(DocsLinks, MarkdownLinkTargetsExist) {
    const std::regex link(R"(\]\(([^()\s]+)\))");
    int checked = 0;
    for (const fs::path& md : markdown_files()) {
        const std::string text = read(kRoot / md);
        for (auto it = std::sregex_iterator(text.begin(), text.end(), link);
             it != std::sregex_iterator(); ++it) {
            std::string target = (*it)[1].str();
            if (target.rfind("http://", 0) == 0 || target.rfind("https://", 0) == 0 ||
                target.rfind("mailto:", 0) == 0 || target[0] == '#') {
                continue;
            }
            if (const auto hash = target.find('#'); hash != std::string::npos) {
                target.resize(hash);
            }
            const fs::path resolved = (kRoot / md).parent_path() / target;
            EXPECT_TRUE(fs::exists(resolved))
                << md.string() << ":" << line_of(text, it->position()) << ": link target '"
                << (*it)[1].str() << "' does not exist";
            ++checked;
        }
    }
    EXPECT_GT(checked, 10);  // the guide's own links at least
}

TEST(DocsLinks, RepositoryPathsInTheTextExist) {
    const std::set<std::string> dirs = top_dirs();
    ASSERT_TRUE(dirs.count("docs") && dirs.count("scenes"));
    // A word: a run of characters that paths use; a leading "./" is dropped.
    const std::regex word(R"((?:\./)?([A-Za-z0-9_.][A-Za-z0-9_./+\-]*))");
    int checked = 0;
    for (const fs::path& md : markdown_files()) {
        const std::string text = read(kRoot / md);
        for (auto it = std::sregex_iterator(text.begin(), text.end(), word);
             it != std::sregex_iterator(); ++it) {
            std::string w = (*it)[1].str();
            const std::size_t slash = w.find('/');
            if (slash == std::string::npos || !dirs.count(w.substr(0, slash))) continue;
            // Part of a longer token (a URL, "../x", "a/docs/b") is not a repository path.
            const std::size_t at = static_cast<std::size_t>(it->position());
            if (at > 0) {
                const char before = text[at - 1];
                if (before == '/' || before == '.' || before == ':' || before == '-' ||
                    std::isalnum(static_cast<unsigned char>(before))) {
                    continue;
                }
            }
            const std::size_t end = at + static_cast<std::size_t>(it->length());
            if (end < text.size()) {
                const char after = text[end];
                if (after == '<' || after == '*' || after == '{' || after == '$') continue;
                if (text.compare(end, 3, "…") == 0) continue;
            }
            while (!w.empty() && (w.back() == '.' || w.back() == '-')) w.pop_back();
            // Only what reads as a file (an extension in the last part) or a directory (a
            // trailing '/'): `bench/ray_bench` (a program) or `interval/sphere` (a benchmark)
            // name things that are not files of the repository.
            const std::string last = w.substr(w.rfind('/') + 1);
            if (!last.empty() && last.find('.') == std::string::npos) continue;
            EXPECT_TRUE(fs::exists(kRoot / w)) << md.string() << ":" << line_of(text, at) << ": '"
                                               << w << "' is not in the repository";
            ++checked;
        }
    }
    EXPECT_GT(checked, 50);
}

TEST(DocsLinks, NothingOutsideTheRepositoryIsCited) {
    for (const fs::path& md : markdown_files()) {
        const std::string text = read(kRoot / md);
        for (const char* outside : {"../shared", "/work/"}) {
            const std::size_t at = text.find(outside);
            EXPECT_EQ(at, std::string::npos)
                << md.string() << ":" << (at == std::string::npos ? 0 : line_of(text, at))
                << ": cites '" << outside << "', outside the repository";
        }
    }
}

}  // namespace

#include "app/output_paths.h"

#include "app/cli_util.h"
#include "render/atomic_file.h"

#include <sys/stat.h>

#include <filesystem>
#include <optional>
#include <stdexcept>

namespace brume::app {

std::filesystem::path existing_ancestor(const std::filesystem::path& dir) {
    std::filesystem::path p = dir;
    std::error_code ec;
    while (!p.empty() && !std::filesystem::exists(std::filesystem::symlink_status(p, ec))) p = p.parent_path();
    return p.empty() ? std::filesystem::path(".") : p;
}

void check_folder_can_be_made(const std::filesystem::path& dir) {
    const std::filesystem::path base = existing_ancestor(dir);
    std::error_code ec;
    if (!std::filesystem::is_directory(base, ec))
        throw std::runtime_error("cannot create output directory " + dir.string() + ": " + base.string() + " is not a directory");
    check_writable_directory(base);
}

void make_folder(const std::filesystem::path& dir) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec || !std::filesystem::is_directory(dir, ec))
        throw std::runtime_error("cannot create output directory " + dir.string() + (ec ? ": " + ec.message() : ": it is not a directory"));
}

namespace {

namespace fs = std::filesystem;

// What a path reaches: an existing file by device and inode (so hard links and links match), a file
// still to be made by its normalised absolute name.
struct Identity {
    bool exists = false;
    bool device = false;
    dev_t dev = 0;
    ino_t ino = 0;
    fs::path name;
    bool operator==(const Identity& o) const {
        return exists == o.exists && (exists ? dev == o.dev && ino == o.ino : name == o.name);
    }
};

Identity identify(const std::string& path, bool follow_output_links) {
    Identity id;
    struct stat st {};
    if (::stat(path.c_str(), &st) == 0) {
        id.exists = true;
        id.device = S_ISCHR(st.st_mode);
        id.dev = st.st_dev;
        id.ino = st.st_ino;
        return id;
    }
    // A new file: a dangling link leads to the name it will be made under.
    const fs::path target = follow_output_links ? resolve_output(path).path : fs::path(path);
    std::error_code ec;
    id.name = fs::weakly_canonical(fs::absolute(target, ec), ec);
    if (ec) id.name = fs::absolute(target).lexically_normal();
    return id;
}

// The file an output named "-" goes to. A pipe or socket is no file an input or another output can be.
Identity standard_output_identity() {
    Identity id;
    struct stat st {};
    if (::fstat(standard_output_descriptor(), &st) != 0 || S_ISFIFO(st.st_mode) || S_ISSOCK(st.st_mode)) return id;
    id.exists = true;
    id.device = S_ISCHR(st.st_mode);
    id.dev = st.st_dev;
    id.ino = st.st_ino;
    return id;
}

}  // namespace

void check_outputs_distinct(const std::vector<NamedPath>& outputs, const std::vector<NamedPath>& inputs) {
    std::vector<std::pair<const NamedPath*, Identity>> seen;
    for (const NamedPath& in : inputs)
        if (!in.path.empty()) {
            Identity id = identify(in.path, false);
            if (id.exists) seen.emplace_back(&in, id);  // a missing input is reported by its reader
        }
    const std::size_t input_count = seen.size();
    const NamedPath* to_standard_output = nullptr;
    for (const NamedPath& out : outputs) {
        if (out.path.empty()) continue;
        const bool to_stream = names_standard_output(out.path);
        if (to_stream) {  // "-": one stream for one output's bytes
            if (to_standard_output)
                throw UsageError(to_standard_output->option + " and " + out.option +
                                 " both name standard output (- or the file it is open on): at most one output can go there");
            to_standard_output = &out;
        }
        // "-" is the file standard output is open on (`--png - > scene.toml`, or >> it): checked as that
        // file, so that it neither overwrites an input nor lands in the file another output replaces.
        const Identity id = to_stream ? standard_output_identity() : identify(out.path, true);
        if (to_stream && !id.exists) continue;
        const std::string shown = to_stream ? "- (standard output)" : out.path;
        for (std::size_t k = 0; k < seen.size(); ++k) {
            if (!(seen[k].second == id)) continue;
            const NamedPath& other = *seen[k].first;
            if (k < input_count)
                throw UsageError(out.option + " " + shown + " would overwrite " + other.option + " " +
                                            other.path + ": name another output file");
            if (id.device) continue;  // writing twice into /dev/null replaces nothing
            throw UsageError(out.option + " " + shown + " and " + other.option + " " + other.path +
                                        " are the same file: each output needs its own name");
        }
        seen.emplace_back(&out, id);
    }
}

}  // namespace brume::app

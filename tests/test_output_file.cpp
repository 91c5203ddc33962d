// Every file cellfx writes goes through io::OutputFile (fx/internal/io/output_file.hpp): a
// temporary in the target's folder, every write, the fsync and the close checked, then a rename.
// A failure is an fx::Error naming the file and the system's reason, leaves no temporary and
// leaves an existing target as it was.
//
// The failures are made in ways that fail for root too — the suite runs as root in CI, where a
// folder's permission bits (chmod 555) stop nothing:
//   /dev/full                a full disk: every write fails with ENOSPC;
//   /sys                     a folder no one may create files in (EACCES, or EROFS where it is
//                            mounted read-only), root included;
//   a file as a folder       "plain.txt/out.png": ENOTDIR;
//   RLIMIT_FSIZE             in a forked child, with SIGXFSZ ignored: a write part way through
//                            a file fails with EFBIG (a quota or a full disk half way);
// and, only when the suite does not run as root, a folder without write permission.
#include <catch2/catch.hpp>

#include <cerrno>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include "fx/error.hpp"
#include "fx/image.hpp"
#include "fx/plot3d.hpp"
#include "fx/vtk_legacy.hpp"
#include "io/output_file.hpp"
#include "io_test_helpers.hpp"
#include "mesh_builders.hpp"
#include "process_runner.hpp"
#include "test_paths.hpp"
#include "cellfx_names.hpp"

using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

// A fresh, empty folder of the test output.
std::string folder(const std::string& name) {
    const std::string dir = fx_test::output_path("output_file/" + name);
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

// The names in `dir` (a failed write must leave no ".NAME.PID.N.tmp" behind).
std::vector<std::string> names_in(const std::string& dir) {
    std::vector<std::string> names;
    for (const fs::directory_entry& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

fx::Image small_image() {
    fx::Image image(8, 4, glm::vec4(0.25f, 0.5f, 0.75f, 1.0f));
    image.at(1, 2) = glm::vec4(1.0f, 0.0f, 0.0f, 1.0f);
    return image;
}

// Runs `write` in a forked child whose files may not grow past `bytes` (RLIMIT_FSIZE; the
// child ignores SIGXFSZ, so the write that crosses the limit fails with EFBIG instead of
// killing it). The child exits 0 if the write succeeded, 1 with the error's message if it threw.
fx_test::RunResult write_under_file_limit(std::uint64_t bytes, const std::function<void()>& write) {
    return fx_test::run_limited(
        [&] {
            std::signal(SIGXFSZ, SIG_IGN);
            const rlimit limit{bytes, bytes};
            setrlimit(RLIMIT_FSIZE, &limit);
            try {
                write();
            } catch (const fx::Error& e) {
                std::printf("%s\n", e.what());
                return 1;
            }
            return 0;
        },
        {std::uint64_t(2) << 30, 60.0});
}

} // namespace

TEST_CASE("output files: written whole, replacing the target, keeping its permissions", "[io][output]") {
    const std::string dir = folder("whole");
    const std::string path = dir + "/table.csv";
    fx::io::write_output_file(path, "a,b\n1,2\n");
    CHECK(fx_test::read_bytes(path) == "a,b\n1,2\n");
    REQUIRE(chmod(path.c_str(), 0640) == 0);
    fx::io::write_output_file(path, "replaced\n");
    CHECK(fx_test::read_bytes(path) == "replaced\n");
    struct stat s;
    REQUIRE(stat(path.c_str(), &s) == 0);
    CHECK((s.st_mode & 07777) == 0640);
    CHECK(names_in(dir) == std::vector<std::string>{"table.csv"});

    // Streamed in pieces (the PFM writer's rows); nothing is visible under the name until commit.
    {
        fx::io::OutputFile out(path);
        out.write("part one, ");
        CHECK(fx_test::read_bytes(path) == "replaced\n");
        out.write("part two\n");
        out.commit();
    }
    CHECK(fx_test::read_bytes(path) == "part one, part two\n");
    // Abandoned (an exception between writes): the target is untouched, the temporary gone.
    {
        fx::io::OutputFile out(path);
        out.write("never committed");
    }
    CHECK(fx_test::read_bytes(path) == "part one, part two\n");
    CHECK(names_in(dir) == std::vector<std::string>{"table.csv"});

    // Through a symbolic link: the file it points to is replaced, the link kept.
    fs::create_symlink("table.csv", dir + "/link.csv");
    fx::io::write_output_file(dir + "/link.csv", "through the link\n");
    CHECK(fs::is_symlink(dir + "/link.csv"));
    CHECK(fx_test::read_bytes(path) == "through the link\n");
    CHECK(names_in(dir) == std::vector<std::string>{"link.csv", "table.csv"});
}

TEST_CASE("output files: a full disk (/dev/full) is an error naming the file, for every writer", "[io][output]") {
    const std::string dir = folder("full");
    // /dev/full itself: written in place (a device is never replaced by a rename), and fails.
    CHECK_THAT(fx_test::error_message([] { fx::io::write_output_file("/dev/full", "x"); }),
               Contains("/dev/full: cannot write: No space left on device"));
    struct stat s;
    REQUIRE(stat("/dev/full", &s) == 0);
    CHECK(S_ISCHR(s.st_mode)); // still the device
    // Every writer, through a link of the name a user would give.
    const fx::Image image = small_image();
    fx::CellMesh mesh = fx_test::hex_box(1, 1, 1);
    mesh.scalars = {{"s", std::vector<float>(mesh.point_count(), 1.0f)}};
    fx::Plot3dBlock block;
    block.dims = {2, 2, 2};
    for (int i = 0; i < 8; ++i) block.points.push_back(glm::dvec3(i & 1, (i >> 1) & 1, i >> 2));
    const std::vector<std::pair<std::string, std::function<void(const std::string&)>>> writers = {
        {"frame.png", [&](const std::string& p) { fx::write_png(image, p); }},
        {"frame.pfm", [&](const std::string& p) { fx::write_pfm(image, p); }},
        {"mesh.vtk", [&](const std::string& p) { fx::write_vtk_legacy(mesh, p, true); }},
        {"grid.xyz", [&](const std::string& p) { fx::write_plot3d({block}, fx::Plot3dFormat{}, p); }},
    };
    for (const auto& [name, write] : writers) {
        INFO(name);
        const std::string link = dir + "/" + name;
        fs::create_symlink("/dev/full", link);
        CHECK_THAT(fx_test::error_message([&] { write(link); }),
                   Contains(link + ": cannot write: No space left on device"));
        CHECK(fs::is_symlink(link));
    }
}

TEST_CASE("output files: folders that cannot take a file, as root too", "[io][output]") {
    const std::string dir = folder("folders");
    const fx::Image image = small_image();
    SECTION("a folder no one may create files in (/sys): named with the system's reason") {
        REQUIRE(fs::is_directory("/sys")); // Linux's sysfs; present on every machine the suite runs on
        const std::string message = fx_test::error_message([&] { fx::write_png(image, "/sys/cellfx_frame.png"); });
        CHECK_THAT(message, Contains("/sys/cellfx_frame.png: cannot create a file in the folder '/sys'"));
        CHECK((message.find("Permission denied") != std::string::npos ||
               message.find("Read-only file system") != std::string::npos));
        CHECK_FALSE(fs::exists("/sys/cellfx_frame.png"));
    }
    SECTION("a plain file where a folder belongs, a missing folder, a folder as the file") {
        fx::io::write_output_file(dir + "/plain.txt", "a file\n");
        CHECK_THAT(fx_test::error_message([&] { fx::write_pfm(image, dir + "/plain.txt/frame.pfm"); }),
                   Contains(dir + "/plain.txt/frame.pfm: cannot create a file in the folder '" + dir +
                            "/plain.txt': Not a directory"));
        CHECK_THAT(fx_test::error_message([&] { fx::write_png(image, dir + "/missing/frame.png"); }),
                   Contains("frame.png: cannot create a file in the folder '" + dir + "/missing': No such file or directory"));
        CHECK_THAT(fx_test::error_message([&] { fx::write_png(image, dir); }), Contains(dir + ": is a folder, not a file"));
        CHECK_THAT(fx_test::error_message([&] { fx::io::check_output_file(dir + "/missing/x.png"); }),
                   Contains("No such file or directory"));
        CHECK_THAT(fx_test::error_message([&] { fx::io::create_output_folder(dir + "/plain.txt"); }),
                   Contains(dir + "/plain.txt: cannot create the folder"));
        CHECK_THAT(fx_test::error_message([&] { fx::io::create_output_folder(dir + "/plain.txt/below"); }),
                   Contains(dir + "/plain.txt/below: cannot create the folder: Not a directory"));
        fx::io::check_output_file(dir + "/fine.png"); // nothing left behind by the check
        CHECK(names_in(dir) == std::vector<std::string>{"plain.txt"});
    }
    SECTION("a folder without write permission (only when not root: root writes there anyway)") {
        if (geteuid() == 0) {
            WARN("running as root: chmod 555 does not stop root, so /sys stands in for a read-only folder");
            return;
        }
        const std::string locked = dir + "/locked";
        fs::create_directories(locked);
        REQUIRE(chmod(locked.c_str(), 0555) == 0);
        CHECK_THAT(fx_test::error_message([&] { fx::write_png(image, locked + "/frame.png"); }),
                   Contains("cannot create a file in the folder '" + locked + "': Permission denied"));
        chmod(locked.c_str(), 0755);
    }
}

TEST_CASE("output files: a write that fails part way leaves the old file and no temporary", "[io][output]") {
    const std::string dir = folder("part_way");
    const std::string path = dir + "/frame.pfm";
    fx::io::write_output_file(path, "the last good frame\n");
    // 64 KiB of file at most; the image needs 200 x 100 x 12 bytes = 240,000.
    const fx::Image big(200, 100, glm::vec4(0.5f));
    const fx_test::RunResult r = write_under_file_limit(64 << 10, [&] { fx::write_pfm(big, path); });
    INFO(r.describe());
    CHECK(r.exit_code == 1);
    CHECK_THAT(r.output, Contains(path + ": cannot write: File too large"));
    CHECK(fx_test::read_bytes(path) == "the last good frame\n");
    CHECK(names_in(dir) == std::vector<std::string>{"frame.pfm"});
    // The same image within the limit is written whole.
    const fx_test::RunResult ok = write_under_file_limit(1 << 20, [&] { fx::write_pfm(big, path); });
    INFO(ok.describe());
    CHECK(ok.exit_code == 0);
    const fx::Image back = fx::read_pfm(path);
    CHECK(back.width == 200);
    CHECK(back.height == 100);
    CHECK(names_in(dir) == std::vector<std::string>{"frame.pfm"});
}

// Transfer functions: evaluation, rescaling, the JSON form and every error it reports.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <string>

#include "fx/error.hpp"
#include "transfer/segment_integral.hpp"
#include "fx/transfer_function.hpp"
#include "test_paths.hpp"
#include "cellfx_names.hpp"

namespace {

using glm::dvec3;

fx::TransferFunction parse(const std::string& text) { return fx::TransferFunction::parse_json(text, "fire.json"); }

} // namespace

TEST_CASE("transfer function evaluates linearly, holds its ends and steps right-continuously", "[transfer]") {
    const fx::TransferFunction tf({{0.0, dvec3(0, 0, 0), 0.0},
                                   {1.0, dvec3(1, 0.5, 0), 2.0},
                                   {1.0, dvec3(0, 0, 1), 10.0},
                                   {3.0, dvec3(0, 0, 0), 0.0}});
    CHECK(tf.color(0.5) == dvec3(0.5, 0.25, 0));
    CHECK(tf.sigma(0.25) == 0.5);
    CHECK(tf.sigma(1.0) == 10.0); // the value from above at the step
    CHECK(tf.color(1.0) == dvec3(0, 0, 1));
    CHECK(tf.sigma(std::nextafter(1.0, 0.0)) == Approx(2.0));
    CHECK(tf.sigma(2.0) == 5.0);
    CHECK(tf.sigma(-7.0) == 0.0); // held ends
    CHECK(tf.color(99.0) == dvec3(0.0));
    CHECK(tf.emission(0.5) == dvec3(0.5, 0.25, 0) * 1.0);
    CHECK_FALSE(tf.normalized());

    const fx::TransferFunction c = fx::TransferFunction::constant(dvec3(0.2, 0.4, 0.6), 3.0);
    CHECK(c.points().size() == 1);
    CHECK(c.color(-1e300) == dvec3(0.2, 0.4, 0.6));
    CHECK(c.sigma(1e300) == 3.0);

    const fx::TransferFunction empty;
    CHECK(empty.sigma(0.0) == 0.0);
    CHECK(fx::emission_absorption(empty, 0.0, 1.0, 1.0).alpha == 0.0);
}

TEST_CASE("the constructor rejects bad points", "[transfer]") {
    using P = fx::TransferPoint;
    const double nan = std::nan(""), inf = INFINITY;
    CHECK_THROWS_WITH(fx::TransferFunction(std::vector<fx::TransferPoint>{}), Catch::Contains("at least 1 point"));
    CHECK_THROWS_WITH(fx::TransferFunction({{0, dvec3(0), 1}, {nan, dvec3(0), 1}}), Catch::Contains("points[1]: s is not finite"));
    CHECK_THROWS_WITH(fx::TransferFunction({P{0, dvec3(0, inf, 0), 1}}), Catch::Contains("points[0]: g is not finite"));
    CHECK_THROWS_WITH(fx::TransferFunction({P{0, dvec3(0), nan}}), Catch::Contains("points[0]: sigma is not finite"));
    CHECK_THROWS_WITH(fx::TransferFunction({P{0, dvec3(-0.1, 0, 0), 1}}), Catch::Contains("points[0]: r is negative"));
    CHECK_THROWS_WITH(fx::TransferFunction({{0, dvec3(0), 1}, {1, dvec3(0), -1}}), Catch::Contains("points[1]: sigma is negative"));
    CHECK_THROWS_WITH(fx::TransferFunction({{0, dvec3(0), 1}, {-1, dvec3(0), 1}}), Catch::Contains("points[1]: s decreases"));
    CHECK_THROWS_WITH(fx::TransferFunction({{0, dvec3(0), 1}, {0, dvec3(0), 2}, {0, dvec3(0), 3}}),
                      Catch::Contains("points[2]: s = 0 appears more than twice"));
    CHECK_THROWS_WITH(fx::TransferFunction({{0.5, dvec3(0), 1}, {1, dvec3(0), 1}}, true),
                      Catch::Contains("must run from s = 0 to s = 1"));
    CHECK_NOTHROW(fx::TransferFunction({{0, dvec3(0), 0}, {0, dvec3(1), 1}, {1, dvec3(1), 1}, {1, dvec3(0), 0}}, true));
}

TEST_CASE("rescaled maps the s range, mirrors for lo > hi, keeps steps", "[transfer]") {
    const fx::TransferFunction tf({{0.0, dvec3(1, 0, 0), 1.0}, {0.25, dvec3(0, 1, 0), 2.0}, {0.25, dvec3(0, 0, 1), 4.0},
                                   {1.0, dvec3(1, 1, 1), 8.0}},
                                  true);
    CHECK(tf.normalized());
    const fx::TransferFunction r = tf.rescaled(10.0, 50.0);
    CHECK_FALSE(r.normalized());
    REQUIRE(r.points().size() == 4);
    CHECK(r.points()[0].s == 10.0);
    CHECK(r.points()[1].s == 20.0);
    CHECK(r.points()[2].s == 20.0);
    CHECK(r.points()[3].s == 50.0);
    CHECK(r.sigma(20.0) == 4.0);
    CHECK(r.sigma(35.0) == Approx(tf.sigma(0.625)));

    const fx::TransferFunction m = tf.rescaled(1.0, -1.0); // s → 1 − 2s
    CHECK(m.points().front().s == -1.0);
    CHECK(m.points().back().s == 1.0);
    for (double s : {0.0, 0.1, 0.3, 0.9, 1.0}) CHECK(m.sigma(1.0 - 2.0 * s) == Approx(tf.sigma(s)));
    // Across the mirrored step: below 0.5 is the old "above 0.25" side.
    CHECK(m.sigma(0.49) == Approx(tf.sigma(0.255)));
    CHECK(m.sigma(0.51) == Approx(tf.sigma(0.245)));
    // A segment and its mirror image see the same medium.
    const fx::SegmentColor a = fx::emission_absorption(tf, 0.1, 0.8, 2.0);
    const fx::SegmentColor b = fx::emission_absorption(m, 0.8, -0.6, 2.0);
    CHECK(b.color.r == Approx(a.color.r).epsilon(1e-12));
    CHECK(b.alpha == Approx(a.alpha).epsilon(1e-12));

    // A constant field: the value at the function's first s, from above (here the step's
    // first point is s = 0 alone, so its own value), as if the range were [2, 2 + ε].
    const fx::TransferFunction constant = tf.rescaled(2.0, 2.0);
    REQUIRE(constant.points().size() == 1);
    CHECK(constant.points()[0].s == 2.0);
    CHECK(constant.sigma(2.0) == tf.sigma(0.0));
    CHECK(constant.color(-5.0) == tf.color(0.0));
    const fx::TransferFunction stepped({{0.0, dvec3(1, 0, 0), 1.0}, {0.0, dvec3(0, 1, 0), 3.0}, {1.0, dvec3(0), 5.0}}, true);
    CHECK(stepped.rescaled(7.0, 7.0).sigma(7.0) == 3.0); // from above
    CHECK_THROWS_WITH(tf.rescaled(0.0, INFINITY), Catch::Contains("the range of a field must be finite"));
    const fx::TransferFunction single = fx::TransferFunction::constant(dvec3(1), 1.0).rescaled(4.0, 6.0);
    CHECK(single.points()[0].s == 5.0);
}

TEST_CASE("values every path can integrate: sigma up to 1e32, colour up to 1e6", "[transfer]") {
    CHECK_NOTHROW(fx::TransferFunction({{0.0, dvec3(1e6), 1e32}}));
    CHECK_THROWS_WITH(fx::TransferFunction({{0.0, dvec3(1), 1e300}}), Catch::Contains("points[0]: sigma = 1e+300 is over 1e+32"));
    CHECK_THROWS_WITH(fx::TransferFunction({{0.0, dvec3(1, 2e6, 1), 1.0}}), Catch::Contains("points[0]: g = 2e+06 is over 1e+06"));
    CHECK_THROWS_WITH(parse(R"({"points": [[0, 1, 1, 1, 1], [1, 1, 1, 1, 1e33]]})"),
                      Catch::StartsWith("fire.json: points[1]: sigma"));
}

TEST_CASE("JSON that is not UTF-8 says so before parsing", "[transfer]") {
    CHECK_THROWS_WITH(parse(std::string("\xFF\xFE{\0}\0", 6)), Catch::StartsWith("fire.json: is UTF-16 text"));
    CHECK_THROWS_WITH(parse(std::string("\xFE\xFF\0{\0}", 6)), Catch::StartsWith("fire.json: is UTF-16 text"));
    CHECK_THROWS_WITH(parse(std::string("{\0\"\0", 4)), Catch::Contains("byte 1 is a NUL"));
    CHECK_NOTHROW(parse("\xEF\xBB\xBF{\"points\": [[0, 1, 1, 1, 1]]}")); // a UTF-8 byte order mark is fine
}

TEST_CASE("JSON form parses points, steps and normalized", "[transfer]") {
    const fx::TransferFunction tf =
        parse(R"({"description": "test", "normalized": true,
                  "points": [[0, 0, 0, 0, 0], [0.5, 1, 0.5, 0, 2.5], [0.5, 1, 1, 1, 4], [1, 0, 0, 1e-3, 1e2]]})");
    CHECK(tf.normalized());
    REQUIRE(tf.points().size() == 4);
    CHECK(tf.points()[1].color == dvec3(1, 0.5, 0));
    CHECK(tf.points()[1].sigma == 2.5);
    CHECK(tf.points()[3].sigma == 100.0);
    CHECK(tf.sigma(0.5) == 4.0);
    CHECK_FALSE(parse(R"({"points": [[3, 1, 1, 1, 1]]})").normalized());
    CHECK(parse(R"({"points": [[3, 1, 1, 1, 1]], "normalized": false})").points().size() == 1);
}

TEST_CASE("JSON errors name the file, the entry and the problem", "[transfer]") {
    using Catch::Contains;
    // Syntax errors carry nlohmann's byte position.
    CHECK_THROWS_WITH(parse(R"({"points": [[0, 1, 1, 1, 1],]})"), Contains("fire.json: JSON syntax error at byte 29"));
    CHECK_THROWS_WITH(parse(""), Contains("fire.json: JSON syntax error at byte 1"));
    CHECK_THROWS_WITH(parse("[1, 2]"), Contains("fire.json: expected a JSON object"));
    CHECK_THROWS_WITH(parse(R"({"normalized": true})"), Contains("fire.json: missing \"points\""));
    CHECK_THROWS_WITH(parse(R"({"points": {"s": 0}})"), Contains("fire.json: points: must be an array"));
    CHECK_THROWS_WITH(parse(R"({"points": []})"), Contains("fire.json: points: at least 1 point"));
    CHECK_THROWS_WITH(parse(R"({"points": [[0, 1, 1, 1, 1], [1, 1, 1, 1]]})"),
                      Contains("fire.json: points[1]: expected 5 numbers [s, r, g, b, sigma], got [1,1,1,1]"));
    CHECK_THROWS_WITH(parse(R"({"points": [[0, 1, 1, 1, 1, 0]]})"), Contains("fire.json: points[0]: expected 5 numbers"));
    CHECK_THROWS_WITH(parse(R"({"points": [3]})"), Contains("fire.json: points[0]: expected 5 numbers"));
    CHECK_THROWS_WITH(parse(R"({"points": [[0, 1, "red", 1, 1]]})"), Contains("fire.json: points[0]: g is not a number (\"red\")"));
    CHECK_THROWS_WITH(parse(R"({"points": [[0, 1, 1, 1, null]]})"), Contains("fire.json: points[0]: sigma is not a number (null)"));
    CHECK_THROWS_WITH(parse(R"({"points": [[true, 1, 1, 1, 1]]})"), Contains("fire.json: points[0]: s is not a number (true)"));
    // JSON has no NaN or Infinity; an out-of-range number is refused by the parser.
    // Both name the place: the byte and the key path of the number.
    CHECK_THROWS_WITH(parse(R"({"points": [[0, 1, 1, 1, 1e999]]})"),
                      Contains("fire.json: byte 30 (at points[0][4]): the number 1e999 is beyond the range of a double"));
    CHECK_THROWS_WITH(parse(R"({"points": [[-1e400, 1, 1, 1, 1]]})"),
                      Contains("fire.json: byte 19 (at points[0][0]): the number -1e400 is beyond the range of a double"));
    CHECK_THROWS_WITH(parse(R"({"points": [[0, 1, 1, 1, 1], [2, 1, 1, 1, 1e999]], "name": "x"})"),
                      Contains("(at points[1][4]): the number 1e999"));
    CHECK_THROWS_WITH(parse(R"({"points": [[0, 1, 1, 1, NaN]]})"), Contains("fire.json: JSON syntax error at byte 26 (at points[0][4])"));
    CHECK_THROWS_WITH(parse(R"({"points": [[0, 1, 1, 1, Infinity]]})"), Contains("fire.json: JSON syntax error at byte"));
    CHECK_THROWS_WITH(parse(R"({"points": [[0, 0, 0, 0, 0], [1, 0, 0, 0, 0], [2, 0, 0, 0, 0], [3, 0, 0, 0, -2]]})"),
                      Contains("fire.json: points[3]: sigma is negative"));
    CHECK_THROWS_WITH(parse(R"({"points": [[0, 0, -1, 0, 0]]})"), Contains("fire.json: points[0]: g is negative"));
    CHECK_THROWS_WITH(parse(R"({"points": [[0.5, 0, 0, 0, 0], [0.25, 0, 0, 0, 0]]})"),
                      Contains("fire.json: points[1]: s decreases (0.25 after 0.5)"));
    CHECK_THROWS_WITH(parse(R"({"points": [[0.5, 0, 0, 0, 0], [0.5, 0, 0, 0, 1], [0.5, 0, 0, 0, 2]]})"),
                      Contains("fire.json: points[2]: s = 0.5 appears more than twice"));
    CHECK_THROWS_WITH(parse(R"({"points": [[0, 0, 0, 0, 0]], "normalized": "yes"})"),
                      Contains("fire.json: normalized: must be true or false"));
    CHECK_THROWS_WITH(parse(R"({"points": [[0, 0, 0, 0, 0], [2, 0, 0, 0, 0]], "normalized": true})"),
                      Contains("fire.json: a normalized transfer function must run from s = 0 to s = 1 (it runs from 0 to 2)"));
    CHECK_THROWS_WITH(parse(R"({"points": [[0, 0, 0, 0, 0]], "normalised": true})"),
                      Contains("fire.json: unknown key \"normalised\""));
    CHECK_THROWS_WITH(parse(R"({"points": [[0, 0, 0, 0, 0]], "description": 3})"),
                      Contains("fire.json: description: must be a string"));
    CHECK_THROWS_WITH(fx::TransferFunction::read_json("/nonexistent/tf.json"), Contains("/nonexistent/tf.json: cannot open"));
}

TEST_CASE("read_json names the file in errors", "[transfer]") {
    const std::string path = fx_test::output_path("bad_tf.json");
    {
        std::ofstream out(path);
        out << R"({"points": [[0, 1, 1, 1, 1], [1, 1, 1, 1, -0.5]]})";
    }
    CHECK_THROWS_WITH(fx::TransferFunction::read_json(path), Catch::Contains(path + ": points[1]: sigma is negative"));
}

TEST_CASE("the shipped transfer functions load and are normalized", "[transfer]") {
    const std::string dir = fx_test::source_path("content/transfer_functions");
    int count = 0;
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
        if (entry.path().extension() != ".json") continue;
        INFO(entry.path());
        const fx::TransferFunction tf = fx::TransferFunction::read_json(entry.path().string());
        CHECK(tf.normalized());
        CHECK(tf.points().front().s == 0.0);
        CHECK(tf.points().back().s == 1.0);
        ++count;
    }
    CHECK(count >= 4);
    const fx::TransferFunction step = fx::TransferFunction::read_json(dir + "/step.json");
    bool has_step = false;
    for (std::size_t i = 1; i < step.points().size(); ++i) has_step |= step.points()[i].s == step.points()[i - 1].s;
    CHECK(has_step);
    const fx::TransferFunction fog = fx::TransferFunction::read_json(dir + "/fog.json");
    for (const fx::TransferPoint& p : fog.points()) CHECK(p.color == dvec3(1.0));
}

// anima::parse_grid_csv and format_grid_csv: separators, blank lines, line
// ends and a byte order mark, an exact round trip, and every error naming
// the file and line.
#include <anima/core/error.hpp>
#include <anima/poisson/grid_csv.hpp>

#include <doctest/doctest.h>

#include <Eigen/Core>

#include <cmath>
#include <string>

namespace {

std::string error_of(const std::string& text, Eigen::Index rows, Eigen::Index cols) {
    try {
        (void)anima::parse_grid_csv<double>(text, "f.csv", rows, cols);
    } catch (const anima::parse_error& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST_CASE("parse_grid_csv reads rows of numbers with any of its separators") {
    const auto f = anima::parse_grid_csv<double>("\xEF\xBB\xBF" "1, 2;3\r\n\n  \t\r-4.5\t5e-1 6\r1e300,-1e-300,-0\n", "f.csv", 3, 3);
    CHECK(f(0, 0) == 1);
    CHECK(f(0, 2) == 3);
    CHECK(f(1, 0) == -4.5);
    CHECK(f(1, 1) == 0.5);
    CHECK(f(2, 0) == 1e300);
    CHECK(f(2, 1) == -1e-300);
    CHECK(std::signbit(f(2, 2)));
    const auto g = anima::parse_grid_csv<float>("0.25,1\n", "g.csv", 1, 2);
    CHECK(g(0, 0) == 0.25f);
}

TEST_CASE("format_grid_csv writes rows that parse_grid_csv reads back exactly") {
    Eigen::MatrixXd u(2, 3);
    u << 0.1, -1.0 / 3.0, 1e-300, 2, 12345.678901234567, -0.0;
    const std::string text = anima::format_grid_csv(u);
    CHECK(text.substr(0, text.find('\n')) == "0.10000000000000001,-0.33333333333333331,1e-300");
    CHECK(anima::parse_grid_csv<double>(text, "u.csv", 2, 3) == u);
    CHECK(anima::format_grid_csv(Eigen::MatrixXd(0, 0)).empty());
}

TEST_CASE("parse_grid_csv names the file and line of every error") {
    CHECK(error_of("1,2\n3,x\n", 2, 2) == "f.csv:2: 'x' is not a number");
    CHECK(error_of("1,2\n3,4,5\n", 2, 2) == "f.csv:2: more than 2 numbers");
    CHECK(error_of("1,2\n3\n", 2, 2) == "f.csv:2: 1 numbers, expected 2");
    CHECK(error_of("1,2\n\n3,4\n5,6\n", 2, 2) == "f.csv:4: more than the 2 rows of the grid");
    CHECK(error_of("1,2\n\n", 2, 2) == "f.csv:2: the file has 1 rows, the grid 2");
    CHECK(error_of("", 1, 1) == "f.csv:0: the file has 0 rows, the grid 1");
    CHECK(error_of("1,2\n3,nan\n", 2, 2) == "f.csv:2: 'nan' (number 2) is not a finite number");
    CHECK(error_of("-inf,2\n", 1, 2) == "f.csv:1: '-inf' (number 1) is not a finite number");
    // Finite in double, not in float.
    try {
        (void)anima::parse_grid_csv<float>("1\n1e300\n", "g.csv", 2, 1);
        FAIL("no error for 1e300 in float");
    } catch (const anima::parse_error& e) {
        CHECK(std::string(e.what()) == "g.csv:2: '1e300' (number 1) is not a finite number in this precision");
    }
}

TEST_CASE("parse_grid_csv refuses a grid size below 1 before reading") {
    CHECK_THROWS_AS(anima::parse_grid_csv<double>("1\n", "f.csv", 0, 1), anima::invalid_argument);
    CHECK_THROWS_AS(anima::parse_grid_csv<double>("1\n", "f.csv", 1, -2), anima::invalid_argument);
}

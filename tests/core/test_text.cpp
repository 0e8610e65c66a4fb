// anima::text_lines: LF, CRLF and lone CR line ends, a byte order mark, and
// the last line with or without its end.
#include <anima/core/text.hpp>

#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

TEST_CASE("text_lines splits at LF, CRLF and a lone CR") {
    using lines = std::vector<std::string>;
    CHECK(anima::text_lines("a\nb\r\nc\rd") == lines{"a", "b", "c", "d"});
    CHECK(anima::text_lines("a\n\nb\n") == lines{"a", "", "b"});
    CHECK(anima::text_lines("\r\n\r") == lines{"", ""});
    CHECK(anima::text_lines("\xEF\xBB\xBF" "x,y\r") == lines{"x,y"});
    CHECK(anima::text_lines("").empty());
    CHECK(anima::text_lines("\xEF\xBB\xBF").empty());
}

TEST_CASE("whole_number reads a field only when all of it is the number") {
    CHECK(anima::whole_number("2.5") == 2.5);
    CHECK(anima::whole_number("-1e-3") == -1e-3);
    CHECK(anima::whole_number("0x10") == 16.0);
    CHECK(std::isinf(*anima::whole_number("1e999")));
    CHECK(std::isnan(*anima::whole_number("nan")));
    for (const char* bad : {"", " ", "1 ", " 1", "1,", "x", "1.2.3", "--1"}) {
        CAPTURE(bad);
        CHECK_FALSE(anima::whole_number(bad).has_value());
    }
}

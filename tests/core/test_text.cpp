// anima::text_lines: LF, CRLF and lone CR line ends, a byte order mark, and
// the last line with or without its end.
#include <anima/core/text.hpp>

#include <doctest/doctest.h>

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

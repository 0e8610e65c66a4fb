// anima::parse_json: values, lines and errors; against nlohmann/json on
// random documents when that library is installed.
#include <anima/core/json_reader.hpp>

#include <doctest/doctest.h>

#include <cmath>
#include <random>
#include <string>

#if __has_include(<nlohmann/json.hpp>)
#include <nlohmann/json.hpp>
#define ANIMA_TEST_HAVE_NLOHMANN 1
#endif

namespace {

std::string error_of(const std::string& text) {
    try {
        anima::parse_json(text, "t.json");
    } catch (const anima::parse_error& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST_CASE("parse_json reads every kind of value and the line it starts on") {
    const auto doc = anima::parse_json("{\"a\": [1, -2.5e3, 0.125],\n \"b\": {\"c\": true, \"d\": null},\n"
                                       " \"e\": \"x\\ty\\u00e9\\ud83d\\ude00\", \"f\": false}",
                                       "t.json");
    REQUIRE(doc.is_object());
    REQUIRE(doc.object().size() == 4);
    CHECK(doc.object()[0].first == "a");  // members in file order
    CHECK(doc.object()[3].first == "f");
    const auto& a = doc.find("a")->array();
    REQUIRE(a.size() == 3);
    CHECK(a[0].number() == 1.0);
    CHECK(a[1].number() == -2500.0);
    CHECK(a[2].number() == 0.125);
    CHECK(doc.find("a")->line() == 1);
    CHECK(doc.find("b")->line() == 2);
    CHECK(doc.find("b")->find("c")->boolean());
    CHECK(doc.find("b")->find("d")->is_null());
    CHECK(doc.find("e")->string() == "x\ty\xC3\xA9\xF0\x9F\x98\x80");
    CHECK(doc.find("e")->line() == 3);
    CHECK_FALSE(doc.find("f")->boolean());
    CHECK(doc.find("missing") == nullptr);
    CHECK(doc.find("a")->find("a") == nullptr);  // not an object
    CHECK_THROWS_AS((void)doc.find("a")->number(), anima::invalid_argument);
}

TEST_CASE("parse_json: empty containers, a bare value, a byte order mark") {
    CHECK(anima::parse_json("[]", "t").array().empty());
    CHECK(anima::parse_json(" { } ", "t").object().empty());
    CHECK(anima::parse_json("\xEF\xBB\xBF 42", "t").number() == 42.0);
    CHECK(anima::parse_json("\"\"", "t").string().empty());
    CHECK(anima::parse_json("-0", "t").number() == 0.0);
    CHECK(anima::parse_json("1e-400", "t").number() == 0.0);  // underflow to 0, as strtod
    CHECK(anima::parse_json("123456789012345678901234567890", "t").number() == doctest::Approx(1.2345678901234568e29));
}

TEST_CASE("parse_json refuses what RFC 8259 refuses, with file and line") {
    CHECK(error_of("") == "t.json:1: unexpected end of the file, a value was expected");
    CHECK(error_of("{\"a\": 1,}") == "t.json:1: a member name in double quotes was expected");
    CHECK(error_of("[1, 2,]") == "t.json:1: unexpected ']', a value was expected");
    CHECK(error_of("[1\n 2]") == "t.json:2: ',' or ']' was expected in the array that starts on line 1");
    CHECK(error_of("{\"a\": 1\n\n \"b\": 2}") == "t.json:3: ',' or '}' was expected in the object that starts on line 1");
    CHECK(error_of("{\"a\": 1, \"a\": 2}") == "t.json:1: the member \"a\" appears twice");
    CHECK(error_of("// c\n1") == "t.json:1: unexpected '/', a value was expected");
    CHECK(error_of("01") == "t.json:1: unexpected '1' after the JSON value");
    CHECK(error_of("1.") == "t.json:1: a number needs digits after '.'");
    CHECK(error_of(".5") == "t.json:1: unexpected '.', a value was expected");
    CHECK(error_of("-") == "t.json:1: a number needs digits");
    CHECK(error_of("1e") == "t.json:1: a number needs digits in its exponent");
    CHECK(error_of("1e999") == "t.json:1: the number 1e999 is out of range");
    CHECK(error_of("NaN") == "t.json:1: unexpected 'N', a value was expected");
    CHECK(error_of("\n\n\"abc") == "t.json:3: a string is not closed");
    CHECK(error_of("\"a\tb\"") == "t.json:1: a control character inside a string (escape it)");
    CHECK(error_of("\"\\x\"") == "t.json:1: unknown escape '\\x' in a string");
    CHECK(error_of("\"\\u12\"") == "t.json:1: \\u needs four hexadecimal digits");
    CHECK(error_of("\"\\ud83d\"") == "t.json:1: a high surrogate without its low surrogate in \\u escape");
    CHECK(error_of("\"\\ude00\"") == "t.json:1: a lone low surrogate in \\u escape");
    CHECK(error_of("[1] [2]") == "t.json:1: unexpected '[' after the JSON value");
    CHECK(error_of("tru") == "t.json:1: unexpected 't', a value was expected");
}

TEST_CASE("parse_json: deep nesting is an error, not a stack overflow") {
    const std::string deep(100000, '[');
    CHECK(error_of(deep) == "t.json:1: nested more than 64 levels deep");
    std::string ok = std::string(64, '[') + std::string(64, ']');
    CHECK(anima::parse_json(ok, "t").is_array());
    CHECK(error_of(std::string(65, '[') + std::string(65, ']')) == "t.json:1: nested more than 64 levels deep");
}

#ifdef ANIMA_TEST_HAVE_NLOHMANN
namespace {

nlohmann::json random_json(std::mt19937& rng, int depth) {
    std::uniform_int_distribution<int> kind(0, depth > 3 ? 4 : 6);
    std::uniform_real_distribution<double> real(-1e6, 1e6);
    switch (kind(rng)) {
        case 0: return nullptr;
        case 1: return rng() % 2 == 0;
        case 2: return real(rng) * std::pow(10.0, static_cast<int>(rng() % 40) - 20);
        case 3: return static_cast<long long>(rng() % 2000001) - 1000000;
        case 4: {
            std::string s;
            for (int k = static_cast<int>(rng() % 12); k > 0; --k) {
                const int c = static_cast<int>(rng() % 140);
                if (c < 128) s += static_cast<char>(c);  // all of ASCII, control characters too
                else s += "\xC3\xA9";                   // and one two-byte character
            }
            return s;
        }
        case 5: {
            nlohmann::json a = nlohmann::json::array();
            for (int k = static_cast<int>(rng() % 5); k > 0; --k) a.push_back(random_json(rng, depth + 1));
            return a;
        }
        default: {
            nlohmann::json o = nlohmann::json::object();
            for (int k = static_cast<int>(rng() % 5); k > 0; --k)
                o["k" + std::to_string(rng() % 100)] = random_json(rng, depth + 1);
            return o;
        }
    }
}

bool same(const anima::json_value& a, const nlohmann::json& b) {
    if (b.is_null()) return a.is_null();
    if (b.is_boolean()) return a.is_boolean() && a.boolean() == b.get<bool>();
    if (b.is_number()) return a.is_number() && a.number() == b.get<double>();
    if (b.is_string()) return a.is_string() && a.string() == b.get<std::string>();
    if (b.is_array()) {
        if (!a.is_array() || a.array().size() != b.size()) return false;
        for (std::size_t k = 0; k < b.size(); ++k)
            if (!same(a.array()[k], b[k])) return false;
        return true;
    }
    if (!a.is_object() || a.object().size() != b.size()) return false;
    for (const auto& [key, value] : b.items())
        if (!a.find(key) || !same(*a.find(key), value)) return false;
    return true;
}

}  // namespace

TEST_CASE("parse_json reads what nlohmann/json writes, compact and indented") {
    std::mt19937 rng(7);
    for (int n = 0; n < 500; ++n) {
        const nlohmann::json doc = random_json(rng, 0);
        const std::string compact = doc.dump(), indented = doc.dump(2);
        INFO(compact);
        CHECK(same(anima::parse_json(compact, "t"), doc));
        CHECK(same(anima::parse_json(indented, "t"), doc));
    }
}
#else
TEST_CASE("parse_json against nlohmann/json" * doctest::skip()) { MESSAGE("nlohmann/json is not installed"); }
#endif

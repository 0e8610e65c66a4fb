// Checks the JSON an `anima ... --json` run printed: the whole file must be
// one JSON value, and every assertion must hold.
//
//   json_check FILE ASSERTION...
//
// An assertion is "POINTER OP OPERAND" with POINTER a JSON pointer in which
// '*' stands for every element of an array (or member of an object):
//   /frames == 400            OP: == != < <= > >=; OPERAND: a JSON value, or
//   /final < /initial             another pointer (starts with '/')
//   /seams size >= 2          size of an array, object or string
//   /candidates/*/score type number
//                             TYPE: number integer string boolean null array
//                             object
//   /scores exists            the pointer resolves (at least one match for '*')
//   /height ~= 47.8 1e-3      a number within a relative tolerance of another
// Numbers compare as doubles; other values by JSON equality. A pointer with
// '*' must hold for every match, and must match at least once.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <fstream>
#include <iostream>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using json = nlohmann::json;

void collect(const json& v, const std::vector<std::string>& parts, std::size_t i, std::vector<const json*>& out) {
    if (i == parts.size()) {
        out.push_back(&v);
        return;
    }
    const std::string& p = parts[i];
    if (p == "*") {
        if (v.is_array() || v.is_object())
            for (const auto& e : v) collect(e, parts, i + 1, out);
        return;
    }
    if (v.is_object()) {
        const auto it = v.find(p);
        if (it != v.end()) collect(*it, parts, i + 1, out);
    } else if (v.is_array()) {
        if (p.empty() || p.find_first_not_of("0123456789") != std::string::npos) return;
        const std::size_t k = std::stoul(p);
        if (k < v.size()) collect(v[k], parts, i + 1, out);
    }
}

std::vector<const json*> resolve(const json& doc, const std::string& pointer) {
    std::vector<std::string> parts;
    std::size_t start = 1;
    while (start <= pointer.size()) {
        const std::size_t end = pointer.find('/', start);
        std::string part = pointer.substr(start, end == std::string::npos ? std::string::npos : end - start);
        // JSON pointer escapes: ~1 is '/', ~0 is '~'.
        for (std::size_t k; (k = part.find("~1")) != std::string::npos;) part.replace(k, 2, "/");
        for (std::size_t k; (k = part.find("~0")) != std::string::npos;) part.replace(k, 2, "~");
        parts.push_back(part);
        if (end == std::string::npos) break;
        start = end + 1;
    }
    std::vector<const json*> out;
    if (pointer.empty() || pointer == "/") {
        out.push_back(&doc);
        return out;
    }
    collect(doc, parts, 0, out);
    return out;
}

bool has_type(const json& v, const std::string& type) {
    if (type == "number") return v.is_number();
    if (type == "integer") return v.is_number_integer();
    if (type == "string") return v.is_string();
    if (type == "boolean") return v.is_boolean();
    if (type == "null") return v.is_null();
    if (type == "array") return v.is_array();
    if (type == "object") return v.is_object();
    throw std::runtime_error("unknown type '" + type + "'");
}

bool compare(const json& a, const std::string& op, const json& b) {
    if (a.is_number() && b.is_number()) {
        const double x = a.get<double>(), y = b.get<double>();
        if (op == "==") return x == y;
        if (op == "!=") return x != y;
        if (op == "<") return x < y;
        if (op == "<=") return x <= y;
        if (op == ">") return x > y;
        if (op == ">=") return x >= y;
    } else {
        if (op == "==") return a == b;
        if (op == "!=") return a != b;
        if (op == "<" || op == "<=" || op == ">" || op == ">=") return false;  // only numbers are ordered
    }
    throw std::runtime_error("unknown operator '" + op + "'");
}

std::string shown(const json& v) {
    std::string s = v.dump();
    return s.size() > 80 ? s.substr(0, 77) + "..." : s;
}

/// Empty when the assertion holds, else what failed.
std::string check(const json& doc, const std::string& assertion) {
    std::istringstream in(assertion);
    std::string pointer, op;
    in >> pointer >> op;
    std::string rest;
    std::getline(in, rest);
    rest.erase(0, rest.find_first_not_of(' '));
    const auto values = resolve(doc, pointer);
    if (values.empty()) return "no value at " + pointer;
    if (op == "exists") return "";
    for (const json* v : values) {
        if (op == "type") {
            if (!has_type(*v, rest)) return pointer + " is " + shown(*v) + ", not of type " + rest;
            continue;
        }
        json lhs = *v;
        std::string cmp = op, operand = rest;
        if (op == "size") {
            if (!v->is_array() && !v->is_object() && !v->is_string()) return pointer + " has no size";
            lhs = v->is_string() ? v->get<std::string>().size() : v->size();
            std::istringstream r(rest);
            r >> cmp;
            std::getline(r, operand);
            operand.erase(0, operand.find_first_not_of(' '));
        }
        if (cmp == "~=") {  // OPERAND is "VALUE-OR-POINTER REL"
            std::istringstream r(operand);
            std::string target;
            double rel = 0;
            r >> target >> rel;
            const auto t = target[0] == '/' ? resolve(doc, target) : std::vector<const json*>{};
            const json want = target[0] == '/' ? (t.size() == 1 ? *t[0] : json()) : json::parse(target);
            if (!lhs.is_number() || !want.is_number() || !(rel > 0))
                return pointer + " ~= needs two numbers and a positive relative tolerance";
            const double x = lhs.get<double>(), y = want.get<double>();
            if (!(std::abs(x - y) <= rel * std::max(std::abs(x), std::abs(y))))
                return pointer + " " + shown(lhs) + " is not within " + std::to_string(rel) + " of " + shown(want);
            continue;
        }
        std::vector<const json*> rhs;
        json literal;
        if (!operand.empty() && operand[0] == '/') {
            rhs = resolve(doc, operand);
            if (rhs.size() != 1) return operand + " must name exactly one value";
        } else {
            literal = json::parse(operand);
            rhs.push_back(&literal);
        }
        if (!compare(lhs, cmp, *rhs[0]))
            return pointer + (op == "size" ? " size " : " ") + shown(lhs) + " " + cmp + " " + shown(*rhs[0]) +
                   " does not hold";
    }
    return "";
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 3) {
        std::cerr << "usage: json_check FILE ASSERTION...\n";
        return 2;
    }
    std::ifstream file(argv[1], std::ios::binary);
    const std::string text((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
    json doc;
    try {
        doc = json::parse(text);  // throws on anything but exactly one value
    } catch (const std::exception& e) {
        std::cerr << "json_check: " << argv[1] << " is not one JSON value: " << e.what() << "\n";
        return 1;
    }
    int failed = 0;
    for (int i = 2; i < argc; ++i) {
        std::string problem;
        try {
            problem = check(doc, argv[i]);
        } catch (const std::exception& e) {
            problem = std::string("bad assertion: ") + e.what();
        }
        if (!problem.empty()) {
            std::cerr << "json_check: '" << argv[i] << "': " << problem << "\n";
            ++failed;
        }
    }
    return failed == 0 ? 0 : 1;
}

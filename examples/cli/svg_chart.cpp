#include "svg_chart.hpp"

#include <algorithm>
#include <cmath>

namespace anima_cli {

double chart_panel::x(double v) const { return left + width * (v - x0) / (x1 != x0 ? x1 - x0 : 1.0); }

double chart_panel::y(double v) const { return top + height * (1 - (v - y0) / (y1 != y0 ? y1 - y0 : 1.0)); }

void chart_panel::y_axis(int ticks, bool grid) const {
    for (const double v : nice_ticks(std::min(y0, y1), std::max(y0, y1), ticks)) {
        if (grid) svg->line(left, y(v), right(), y(v), "#e4e4e4", 1);
        else svg->line(left - 4, y(v), left, y(v), "#444", 1);
        svg->text(left - 6, y(v) + 4, format_number(v, 10), 11, "#444", "end");
    }
    svg->line(left, top, left, bottom(), "#444", 1);
    svg->line(left, bottom(), right(), bottom(), "#444", 1);
}

void chart_panel::shade(double a, double b, std::string_view fill) const {
    const double xa = std::max(left, x(a)), xb = std::min(right(), x(b));
    if (xb > xa) svg->rect(xa, top, std::max(1.0, xb - xa), height, fill);
}

void chart_panel::series(const std::vector<double>& v, double x_first, double dx, std::string_view colour,
                         double stroke, mark style) const {
    std::string points;
    const auto flush = [&] {
        if (!points.empty())
            svg->raw("<polyline fill=\"none\" stroke=\"" + std::string(colour) + "\" stroke-width=\"" +
                     svg_number(stroke) + (style == mark::dashed ? "\" stroke-dasharray=\"5,3\" opacity=\"0.8" : "") +
                     "\" stroke-linejoin=\"round\" points=\"" + points + "\"/>");
        points.clear();
    };
    const double lo = std::min(x0, x1) - 1e-9 * std::abs(x1 - x0), hi = std::max(x0, x1) + 1e-9 * std::abs(x1 - x0);
    for (std::size_t k = 0; k < v.size(); ++k) {
        const double at = x_first + static_cast<double>(k) * dx;
        if (!std::isfinite(v[k]) || at < lo || at > hi) {
            flush();
            continue;
        }
        const double py = std::clamp(y(v[k]), top, bottom());
        points += (points.empty() ? "" : " ") + svg_number(x(at)) + "," + svg_number(py);
    }
    flush();
}

namespace {

void draw_mark(svg_document& svg, double x, double y, mark shape, std::string_view colour) {
    if (shape == mark::dot) return svg.circle(x, y, 3.2, colour);
    if (shape == mark::box) return svg.rect(x - 7, y - 5, 14, 10, colour);
    if (shape == mark::line || shape == mark::dashed)
        return svg.raw("<line x1=\"" + svg_number(x - 8) + "\" y1=\"" + svg_number(y) + "\" x2=\"" + svg_number(x + 8) +
                       "\" y2=\"" + svg_number(y) + "\" stroke=\"" + std::string(colour) + "\" stroke-width=\"2\"" +
                       (shape == mark::dashed ? " stroke-dasharray=\"4,2\"" : "") + "/>");
    const double s = 6, tip = shape == mark::up ? y - s : y + s, base = shape == mark::up ? y + s * 0.6 : y - s * 0.6;
    svg.raw("<polygon points=\"" + svg_number(x - s) + "," + svg_number(base) + " " + svg_number(x + s) + "," +
            svg_number(base) + " " + svg_number(x) + "," + svg_number(tip) + "\" fill=\"" + std::string(colour) +
            "\"/>");
}

}  // namespace

void chart_panel::marker(double px, double py, mark shape, std::string_view colour) const {
    draw_mark(*svg, x(px), y(py), shape, colour);
}

svg_chart::svg_chart(double width, const std::string& title, const std::string& subtitle, double left, double right)
    : svg_(width, 0, title), left_(left), right_(right), cursor_(subtitle.empty() ? 36 : 52) {
    svg_.text(width / 2, 22, title, 14, "#222", "middle", true);
    if (!subtitle.empty()) svg_.text(width / 2, 40, subtitle, 11, "#555", "middle");
}

chart_panel svg_chart::panel(double height, double x0, double x1, double y0, double y1, const std::string& label,
                             double width) {
    cursor_ += label.empty() ? 8 : 22;
    if (!label.empty()) svg_.text(left_, cursor_ - 8, label, 12, "#222");
    chart_panel p{&svg_, left_, cursor_, width > 0 ? width : right() - left_, height, x0, x1, y0, y1};
    cursor_ += height;
    return p;
}

void svg_chart::x_axis(const chart_panel& p, int ticks, const std::string& label) {
    const double y = p.bottom();
    for (const double v : nice_ticks(std::min(p.x0, p.x1), std::max(p.x0, p.x1), ticks)) {
        svg_.line(p.x(v), y, p.x(v), y + 4, "#444", 1);
        svg_.text(p.x(v), y + 16, format_number(v, 10), 11, "#444", "middle");
    }
    svg_.text((p.left + p.right()) / 2, y + 34, label, 12, "#222", "middle");
    cursor_ = std::max(cursor_, y + 40);
}

void svg_chart::legend(const std::vector<legend_entry>& entries, const std::string& note) {
    const double y = cursor_ + 16;
    double x = left_;
    for (const auto& e : entries) {
        draw_mark(svg_, x + 8, y - 4, e.swatch, e.colour);
        svg_.text(x + 20, y, e.text, 12, "#333");
        x += 34 + 7 * static_cast<double>(e.text.size());
    }
    if (!note.empty()) svg_.text(right(), y, note, 12, "#444", "end");
    cursor_ = y + 8;
}

std::string svg_chart::str() {
    svg_.set_height(cursor_ + 12);
    return svg_.str();
}

void colour_bar(svg_document& svg, double x, double top, double height, std::string_view id,
                const std::vector<std::string>& stops, const std::vector<std::pair<std::string, double>>& labels) {
    std::string defs = "<defs><linearGradient id=\"" + std::string(id) + "\" x1=\"0\" y1=\"1\" x2=\"0\" y2=\"0\">";
    for (std::size_t k = 0; k < stops.size(); ++k)
        defs += "<stop offset=\"" + svg_number(static_cast<double>(k) / static_cast<double>(stops.size() - 1)) +
                "\" stop-color=\"" + stops[k] + "\"/>";
    svg.raw(defs + "</linearGradient></defs>");
    svg.rect(x, top, 14, height, "url(#" + std::string(id) + ")", "#444", 0.5);
    for (const auto& [text, y] : labels) svg.text(x + 20, top + y, text, 10, "#333");
}

}  // namespace anima_cli

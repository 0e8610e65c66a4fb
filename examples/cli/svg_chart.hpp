// The charts of the `anima` subcommands' plots (contacts, flight,
// transition, symmetry, texture): a title, panels stacked top to bottom
// with data coordinates, axes with ticks and labels, polyline series,
// shaded x-intervals, markers, a legend and a colour bar, drawn with the
// svg_document of common.hpp.
#pragma once

#include "common.hpp"

#include <string>
#include <string_view>
#include <vector>

namespace anima_cli {

/// How a series or a legend entry is drawn.
enum class mark { line, dashed, box, dot, up, down };

/// A rectangle of the chart with data coordinates: x from x0 (left) to x1
/// (right), y from y0 (bottom) to y1 (top); y1 < y0 turns the y axis over.
struct chart_panel {
    svg_document* svg = nullptr;
    double left = 0, top = 0, width = 0, height = 0;
    double x0 = 0, x1 = 1, y0 = 0, y1 = 1;

    double x(double v) const;
    double y(double v) const;
    double right() const { return left + width; }
    double bottom() const { return top + height; }

    /// The frame (lines at the left and the bottom) and the y axis: about
    /// `ticks` labelled values, light grid lines across (or tick marks only).
    void y_axis(int ticks, bool grid = true) const;
    /// A shaded band over x in [a, b], clipped to the panel.
    void shade(double a, double b, std::string_view fill) const;
    /// y[k] at x0 + k * dx as a polyline; non-finite values and points
    /// outside x0..x1 are gaps, values outside the y range are clamped.
    void series(const std::vector<double>& y, double x_first, double dx, std::string_view colour, double stroke = 1.5,
                mark style = mark::line) const;
    /// A dot or a triangle at (x, y).
    void marker(double x, double y, mark shape, std::string_view colour) const;
};

/// A legend entry: its mark in its colour, then the text.
struct legend_entry {
    std::string colour, text;
    mark swatch = mark::line;
};

/// A figure of stacked panels. Each panel(), x_axis() and legend() adds
/// below what is there; the height follows when the figure is written.
class svg_chart {
public:
    /// `width` pixels wide, panels from `left` to `width - right`; the title
    /// bold at the top, the subtitle (if any) under it.
    svg_chart(double width, const std::string& title, const std::string& subtitle = {}, double left = 70,
              double right = 24);

    /// A panel `height` pixels high under the last, `label` above its left
    /// end; `width` 0 spans the chart.
    chart_panel panel(double height, double x0, double x1, double y0, double y1, const std::string& label = {},
                      double width = 0);
    /// Empty space under the last panel.
    void skip(double pixels) { cursor_ += pixels; }
    /// The x axis under `p`: about `ticks` labelled values and `label`
    /// centred below.
    void x_axis(const chart_panel& p, int ticks, const std::string& label);
    /// A row of legend entries, and a note at the right end.
    void legend(const std::vector<legend_entry>& entries, const std::string& note = {});

    svg_document& svg() { return svg_; }
    double left() const { return left_; }
    double right() const { return svg_.width() - right_; }
    double cursor() const { return cursor_; }
    /// The figure as SVG text, as tall as what was added.
    std::string str();

private:
    svg_document svg_;
    double left_, right_, cursor_;
};

/// A vertical colour bar `height` pixels high at (x, top): `stops` from
/// bottom to top as SVG colours, each `labels` line (text, y from the top)
/// to its right.
void colour_bar(svg_document& svg, double x, double top, double height, std::string_view id,
                const std::vector<std::string>& stops, const std::vector<std::pair<std::string, double>>& labels);

}  // namespace anima_cli

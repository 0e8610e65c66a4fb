// The answer of a max-flow / min-cut computation: the flow value and, for
// every node, the side of the minimum cut it is on.
#pragma once

#include <algorithm>
#include <cstddef>
#include <string_view>
#include <vector>

namespace anima {

/// The side of a minimum cut a node is on.
enum class cut_side : unsigned char { source, sink };

inline std::string_view to_string(cut_side s) { return s == cut_side::source ? "source" : "sink"; }

/// A maximum flow and the minimum cut it saturates. The source side holds
/// exactly the nodes reachable from the source through edges with residual
/// capacity, the smallest source side of all minimum cuts; every other node is
/// on the sink side. The capacity of the cut (edges from the source side to
/// the sink side, source edges of sink-side nodes, sink edges of source-side
/// nodes) equals `flow`.
template <class Flow>
struct min_cut_result {
    Flow flow{};
    std::vector<cut_side> side;  ///< per node, in node id order

    std::size_t source_count() const {
        return static_cast<std::size_t>(std::count(side.begin(), side.end(), cut_side::source));
    }
    std::size_t sink_count() const { return side.size() - source_count(); }
};

}  // namespace anima

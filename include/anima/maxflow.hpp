// Max-flow / min-cut: the Boykov-Kolmogorov algorithm on general graphs
// (flow_graph) and on rows x cols lattices (grid_flow_graph), templated on
// the capacity type, and a reader for the DIMACS max-flow format.
#pragma once

#include <anima/maxflow/capacity.hpp>
#include <anima/maxflow/dimacs.hpp>
#include <anima/maxflow/graph.hpp>
#include <anima/maxflow/grid_graph.hpp>
#include <anima/maxflow/min_cut.hpp>

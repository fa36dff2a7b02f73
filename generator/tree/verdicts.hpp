// The verdicts the tree stage has the model remember (ModelQuery::verdict), each kind's question
// opening with its own value: within a job the same strut, square or prism is judged again and
// again (the three ways a tree grows from the same leaves, every region priced over the same
// samples), and each verdict takes several questions to the model.
#pragma once

#include <cstddef>
#include <initializer_list>

#include "query/model_query.hpp"

namespace cs {

enum class TreeVerdict { strut = 1, square, prism, fan_reach };

// The question: the kind, then the values the verdict depends on besides the model (at most 11).
inline ModelQuery::Question tree_question(TreeVerdict kind, std::initializer_list<double> values) {
    ModelQuery::Question q{};
    q[0] = static_cast<double>(kind);
    std::size_t i = 1;
    for (const double v : values) q[i++] = v;
    return q;
}

}  // namespace cs

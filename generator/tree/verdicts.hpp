// The verdicts the tree stage has the model remember (ModelQuery::verdict), each kind's question
// opening with its own value: within a job the same strut, square or prism is judged again and
// again (the three ways a tree grows from the same leaves, every region priced over the same
// samples), and each verdict takes several questions to the model.
#pragma once

#include <array>
#include <cstddef>

#include "query/model_query.hpp"

namespace cs {

enum class TreeVerdict { strut = 1, square, prism, fan_reach };

// The question: the kind, then the values the verdict depends on besides the model (at most 11,
// checked when it compiles).
template <std::size_t N>
ModelQuery::Question tree_question(TreeVerdict kind, const double (&values)[N]) {
    ModelQuery::Question q{};
    static_assert(N < std::tuple_size_v<ModelQuery::Question>, "a question holds its kind and at most 11 values");
    q[0] = static_cast<double>(kind);
    for (std::size_t i = 0; i < N; ++i) q[i + 1] = values[i];
    return q;
}

}  // namespace cs

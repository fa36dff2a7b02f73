#include "cli/suggest.hpp"

#include <algorithm>
#include <cctype>

namespace cs {

int edit_distance(const std::string& a0, const std::string& b0) {
    std::string a = a0, b = b0;
    for (auto* s : {&a, &b})
        std::transform(s->begin(), s->end(), s->begin(), [](unsigned char c) { return std::tolower(c); });
    const size_t n = a.size(), m = b.size();
    // d[i][j]: a's first i letters into b's first j (optimal string alignment).
    std::vector<std::vector<int>> d(n + 1, std::vector<int>(m + 1, 0));
    for (size_t i = 0; i <= n; ++i) d[i][0] = static_cast<int>(i);
    for (size_t j = 0; j <= m; ++j) d[0][j] = static_cast<int>(j);
    for (size_t i = 1; i <= n; ++i)
        for (size_t j = 1; j <= m; ++j) {
            d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (a[i - 1] != b[j - 1])});
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
                d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
        }
    return d[n][m];
}

namespace {

// Letters two words share from their start, leading dashes not counted.
size_t shared_start(const std::string& a, const std::string& b) {
    size_t i = 0;
    while (i < a.size() && i < b.size() && std::tolower((unsigned char)a[i]) == std::tolower((unsigned char)b[i])) ++i;
    size_t dashes = 0;
    while (dashes < i && a[dashes] == '-') ++dashes;
    return i - dashes;
}

}  // namespace

std::string closest_word(const std::string& typed, const std::vector<std::string>& known) {
    if (typed.empty()) return "";
    // A slip, not another word: at most a third of the letters, and never more than three.
    const int allowed = std::clamp(static_cast<int>(typed.size()) / 3, 1, 3);
    std::string best;
    int best_d = allowed + 1;
    for (const auto& w : known)
        if (const int d = edit_distance(typed, w); d < best_d) best = w, best_d = d;
    if (!best.empty()) return best;
    // Else the one word that starts as it does for longest, from four letters on ("--sampel").
    size_t longest = 0;
    int with_longest = 0;
    for (const auto& w : known) {
        const size_t n = shared_start(typed, w);
        if (n > longest) longest = n, best = w, with_longest = 1;
        else if (n == longest) ++with_longest;
    }
    return longest >= 4 && with_longest == 1 ? best : "";
}

std::string did_you_mean(const std::string& typed, const std::vector<std::string>& known) {
    const std::string w = closest_word(typed, known);
    return w.empty() ? "" : " (did you mean `" + w + "`?)";
}

}  // namespace cs

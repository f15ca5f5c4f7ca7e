// "Did you mean …?" for a misspelt name: the candidate nearest to a word by edit distance
// (insertions, deletions, substitutions and swaps of neighbouring characters each count 1: the
// optimal string alignment distance), if it is near enough to be a likely typo.
#pragma once

#include <algorithm>
#include <string>
#include <vector>

namespace lobe {

inline int editDistance(const std::string& a, const std::string& b) {
    const size_t n = a.size(), m = b.size();
    std::vector<std::vector<int>> d(n + 1, std::vector<int>(m + 1));
    for (size_t i = 0; i <= n; ++i) d[i][0] = int(i);
    for (size_t j = 0; j <= m; ++j) d[0][j] = int(j);
    for (size_t i = 1; i <= n; ++i)
        for (size_t j = 1; j <= m; ++j) {
            const int cost = a[i - 1] == b[j - 1] ? 0 : 1;
            d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
                d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
        }
    return d[n][m];
}

// The candidate within `maxDistance` edits of `word` (the first of the nearest, in the
// candidates' order), or "" when none is. Nothing is suggested for words of one or two
// characters, where any short name would be "near".
template <class Names>
std::string nearestName(const std::string& word, const Names& candidates, int maxDistance = 2) {
    std::string best;
    int bestDistance = maxDistance + 1;
    const int limit = std::min<int>(maxDistance, int(word.size()) - 1);
    for (const std::string& c : candidates) {
        if (c == word) continue;
        const int dist = editDistance(word, c);
        if (dist <= limit && dist < bestDistance) {
            best = c;
            bestDistance = dist;
        }
    }
    return best;
}

}  // namespace lobe

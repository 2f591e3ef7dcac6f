// When a guided render learns: Müller et al. 2017's training in iterations of doubling sample
// counts (1, 2, 4, ... per pixel), each sampling the field learnt by the one before and
// recording into the next, then a last iteration that samples the final field and records
// nothing. Every sample of every iteration goes to the film: each is an unbiased estimate,
// the early ones only noisier (the paper keeps the last iteration alone; keeping them all
// wastes no time, and the film, its checkpoints and split renders stay as they are).
//
// Training stops at half the samples: the iterations continue while they end within spp / 2,
// so the last, frozen iteration has at least half the render. (Müller's automatic budget
// compares measured variances against time, which would make the image depend on the
// machine's speed; a sample budget keeps it a function of the seed.)
#pragma once
#include <vector>

namespace spt {

/// The sample counts at which the iterations of a guided render of `spp` samples per pixel
/// end: 1, 3, 7, ... (training), then spp (the last iteration).
inline std::vector<int> guiding_iteration_ends(int spp) {
    std::vector<int> ends;
    int used = 0;
    for (int size = 1; used + size <= spp / 2; size *= 2) {
        used += size;
        ends.push_back(used);
    }
    if (ends.empty() || ends.back() < spp) ends.push_back(spp);
    return ends;
}

}  // namespace spt

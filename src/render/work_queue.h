// The queue worker threads take their tasks from, in one of three implementations chosen at
// run time (--queue): measured against each other in validation/parallel_strategies.py.
#pragma once
#include <cstddef>
#include <optional>
#include <span>
#include <string_view>
#include <variant>

#include "render/counter_queue.h"
#include "render/mutex_queue.h"
#include "render/ring_queue.h"

namespace spt {

enum class QueueKind { mutex, ring, counter };

/// "mutex", "ring", "atomic" (the counter queue); nullopt for any other name.
inline std::optional<QueueKind> queue_kind_from_name(std::string_view name) {
    if (name == "mutex") return QueueKind::mutex;
    if (name == "ring") return QueueKind::ring;
    if (name == "atomic") return QueueKind::counter;
    return std::nullopt;
}
inline const char* queue_kind_name(QueueKind kind) {
    return kind == QueueKind::mutex ? "mutex" : kind == QueueKind::ring ? "ring" : "atomic";
}

/// One producer pushes batches of items, many workers pop them until the queue is closed and
/// drained. Every kind hands out each item exactly once, in push order; the counter queue
/// also needs the previous batch finished before a push (the renderer always waits for it).
template <typename T>
class WorkQueue {
public:
    /// `capacity`: the ring's size (the most items it holds at once; the other kinds grow).
    WorkQueue(QueueKind kind, std::size_t capacity) {
        if (kind == QueueKind::ring) m_queue.template emplace<RingQueue<T>>(capacity);
        else m_queue.template emplace<CounterQueue<T>>();
    }
    void push(std::span<const T> items) {
        std::visit([&](auto& q) { q.push(items); }, m_queue);
    }
    std::optional<T> pop() {
        return std::visit([](auto& q) { return q.pop(); }, m_queue);
    }
    void close() {
        std::visit([](auto& q) { q.close(); }, m_queue);
    }

private:
    std::variant<MutexQueue<T>, RingQueue<T>, CounterQueue<T>> m_queue;
};

}  // namespace spt

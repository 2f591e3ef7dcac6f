// The three work queues (render/work_queue.h): every item handed out exactly once, in push
// order to a single consumer, batches after batches, and every consumer released by close().
// Depends on the queue headers alone, so it also builds under ThreadSanitizer:
//   g++ -std=c++20 -fsanitize=thread -g -O1 -Isrc tests/test_work_queues.cpp -lgtest -lgtest_main -pthread
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <numeric>
#include <thread>
#include <vector>

#include "render/work_queue.h"

namespace spt {
namespace {

constexpr QueueKind kKinds[] = {QueueKind::mutex, QueueKind::ring, QueueKind::counter};

/// One producer, `consumers` threads: batches of `batch` items, each pushed once the previous
/// one is consumed (the counter queue's contract). Checks that every item is taken once.
void exercise(QueueKind kind, std::size_t capacity, int consumers, int batches, int batch) {
    WorkQueue<int> queue(kind, capacity);
    const int total = batches * batch;
    std::vector<std::atomic<int>> taken(static_cast<std::size_t>(total));
    std::atomic<int> done{0};
    std::vector<std::thread> threads;
    for (int c = 0; c < consumers; ++c)
        threads.emplace_back([&] {
            while (std::optional<int> item = queue.pop()) {
                taken[static_cast<std::size_t>(*item)].fetch_add(1, std::memory_order_relaxed);
                done.fetch_add(1, std::memory_order_release);
            }
        });
    std::vector<int> items(static_cast<std::size_t>(batch));
    for (int b = 0; b < batches; ++b) {
        std::iota(items.begin(), items.end(), b * batch);
        queue.push(items);
        while (done.load(std::memory_order_acquire) < (b + 1) * batch) std::this_thread::yield();
    }
    queue.close();
    for (std::thread& t : threads) t.join();
    for (int i = 0; i < total; ++i)
        ASSERT_EQ(taken[static_cast<std::size_t>(i)].load(), 1) << queue_kind_name(kind) << ": item " << i;
}

TEST(WorkQueues, EveryItemIsTakenExactlyOnce) {
    for (const QueueKind kind : kKinds) {
        exercise(kind, 1024, 1, 20, 100);
        exercise(kind, 1024, 4, 200, 37);
        exercise(kind, 1024, 3, 5, 5000);  // the ring wraps and its producer waits for room
        exercise(kind, 2, 3, 50, 7);       // a tiny ring: full at every other push
    }
}

TEST(WorkQueues, SingleConsumerGetsPushOrder) {
    for (const QueueKind kind : kKinds) {
        WorkQueue<int> queue(kind, 16);
        std::vector<int> items(10);
        std::iota(items.begin(), items.end(), 0);
        queue.push(items);
        for (int i = 0; i < 10; ++i) EXPECT_EQ(queue.pop(), i) << queue_kind_name(kind);
        std::iota(items.begin(), items.end(), 10);  // a second batch after the first is consumed
        queue.push(items);
        for (int i = 10; i < 20; ++i) EXPECT_EQ(queue.pop(), i) << queue_kind_name(kind);
    }
}

/// Workers asleep on an empty queue wake for a later batch and for close(), which also lets
/// them drain what was pushed before it.
TEST(WorkQueues, SleepingConsumersWakeForPushAndClose) {
    for (const QueueKind kind : kKinds) {
        WorkQueue<int> queue(kind, 16);
        std::atomic<int> sum{0}, finished{0};
        std::vector<std::thread> threads;
        for (int c = 0; c < 3; ++c)
            threads.emplace_back([&] {
                while (std::optional<int> item = queue.pop()) sum.fetch_add(*item);
                finished.fetch_add(1);
            });
        std::this_thread::sleep_for(std::chrono::milliseconds(20));  // let them sleep
        EXPECT_EQ(finished.load(), 0) << queue_kind_name(kind) << ": pop returned on an open, empty queue";
        const std::vector<int> items = {1, 2, 3, 4};
        queue.push(items);
        queue.close();
        for (std::thread& t : threads) t.join();
        EXPECT_EQ(sum.load(), 10) << queue_kind_name(kind);
        EXPECT_EQ(finished.load(), 3) << queue_kind_name(kind);
    }
}

TEST(WorkQueues, NamesRoundTrip) {
    for (const QueueKind kind : kKinds) EXPECT_EQ(queue_kind_from_name(queue_kind_name(kind)), kind);
    EXPECT_FALSE(queue_kind_from_name("lockfree"));
}

}  // namespace
}  // namespace spt

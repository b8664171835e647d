// SPDX-License-Identifier: Apache-2.0
/// @file default_init_allocator.h
/// @brief An allocator whose value-less construction default-initialises (trivial elements are
/// left as they are) instead of value-initialising.
///
/// std::vector<T>::resize(n) zero-fills n new elements on the calling thread. A buffer that a
/// parallel loop then overwrites completely pays for that fill and takes every first-touch page
/// fault on one thread; with this allocator resize(n) only allocates, and the loop's own writes
/// spread the faults over the workers. Every element must be written before it is read.
#pragma once

#include <memory>
#include <new>
#include <type_traits>
#include <utility>

namespace kizamu::util {

template <class T, class Base = std::allocator<T>>
class DefaultInitAllocator : public Base {
    using Traits = std::allocator_traits<Base>;

public:
    template <class U>
    struct rebind {
        using other = DefaultInitAllocator<U, typename Traits::template rebind_alloc<U>>;
    };
    using Base::Base;

    template <class U>
    void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
        ::new (static_cast<void*>(p)) U;
    }
    template <class U, class... Args>
    void construct(U* p, Args&&... args) {
        Traits::construct(static_cast<Base&>(*this), p, std::forward<Args>(args)...);
    }
};

}  // namespace kizamu::util

// cellfx — storage kept between frames that stops allocating once it has held a frame's worth.
//
// std::vector's assign(n, value) and assign(first, last) allocate exactly n when n exceeds the
// capacity, and so does resize(n) after clear(): a list one entry longer than any frame's before
// would allocate again in every frame that sets a new maximum, which a moving camera does for a
// long time. These grow the capacity geometrically first (by half, as the GL buffers do) and
// never shrink it.
#pragma once

#include <algorithm>
#include <cstddef>
#include <iterator>
#include <vector>

namespace cellfx::fx {

template <class T>
void reserve_kept(std::vector<T>& v, std::size_t n) {
    if (n > v.capacity()) v.reserve(std::max(n, v.capacity() + v.capacity() / 2));
}

template <class T>
void resize_kept(std::vector<T>& v, std::size_t n) {
    reserve_kept(v, n);
    v.resize(n);
}

template <class T>
void assign_kept(std::vector<T>& v, std::size_t n, const typename std::vector<T>::value_type& value) {
    reserve_kept(v, n);
    v.assign(n, value);
}

template <class T, class Iterator>
void assign_range_kept(std::vector<T>& v, Iterator first, Iterator last) {
    reserve_kept(v, std::size_t(std::distance(first, last)));
    v.assign(first, last);
}

} // namespace cellfx::fx

// No include guard: bvh_wide.h and bvh_wide8.h each include this file once, inside namespace
// rayproof::detail, with RAYPROOF_WIDE_TRAVERSE_LOOP naming the function. bvh_wide8.h includes it
// under `#pragma GCC target("avx2")`, so that the AVX2 box test (always_inline, AVX2) can be
// inlined into the loop: an always_inline AVX2 function cannot be inlined into a baseline one, and
// when it is not inlined the eight-wide traversal pays a call per node. One source, two targets.
#ifndef RAYPROOF_WIDE_TRAVERSE_LOOP
#error "include rayproof/bvh_wide.h, not bvh_wide_loop.h"
#endif

/// The traversal loop of both widths and both node kinds (Tree: BvhWide<N> with full float boxes,
/// BvhWideQ<N> with quantized ones), for the float (T = float) and double (T = double) box tests.
/// `test(node, tmax, t)` returns the hit mask of the node's children and stores their entry
/// distances in t[0 .. N) (at least for the hit ones); `tmax_now()` is the caller's tmax in T.
/// `leaf(first, count)` gets the leaf-order slots [first, first + count) (indices into prim_ids, or
/// into the caller's own leaf-order data) and returns true to stop (any hit); when it also has
/// `prefetch(first)`, that is called for each leaf child put on the stack.
template <class Tree, class T, BvhQuery Query, class BoxTest, class TmaxNow, class Leaf>
[[gnu::always_inline]] inline void RAYPROOF_WIDE_TRAVERSE_LOOP(const Tree& bvh, const BoxTest& test, const TmaxNow& tmax_now,
                                                               Leaf& leaf) {
  using Node = typename Tree::Node;
  constexpr int N = Tree::kWidth;
  using Entry = WideEntry<T>;
  constexpr std::size_t kLocal = N == 4 ? 192 : 256;  // entries on the call stack; deeper trees use the heap
  Entry local[kLocal];
  Entry* stack = local;
  const std::size_t need = (N - 1) * static_cast<std::size_t>(bvh.max_depth) + 8;
  if (need > kLocal) [[unlikely]] {
    // A per-thread buffer that only grows: no vector (and no destructor call) on every ray's path.
    static thread_local std::vector<Entry> heap;
    if (heap.size() < need) heap.resize(need);
    stack = heap.data();
  }
  int top = 0;
  const Node* nodes = bvh.nodes.data();
  T tmax_cur = tmax_now();
  // `e` is the child being visited (its entry already checked against tmax); a visit that ends
  // a path pops the next child whose entry is still within tmax.
  Entry e{0, 0, static_cast<T>(-std::numeric_limits<T>::infinity())};
  if (Query == BvhQuery::closest && !(e.t <= tmax_cur)) return;  // NaN tmax
  for (;;) {
    if (e.count) {
      if (leaf(e.ref, e.count) && Query == BvhQuery::any) return;
      if constexpr (Query == BvhQuery::closest) tmax_cur = tmax_now();
    } else {
      const Node& n = nodes[e.ref];
      alignas(32) T t[N];
      const int mask = test(n, tmax_cur, t);
      if (mask) {
        if ((mask & (mask - 1)) == 0) {  // one child: straight to it
          const int i = __builtin_ctz(static_cast<unsigned>(mask));
          e = Entry{n.child[i], n.count[i], t[i]};
        } else {  // several: for closest hit the nearest next, the farther ones on the stack
          // A leaf callable with prefetch(first) gets it for every leaf child pushed, so that the
          // leaf's data is on its way while the nearer children are visited.
          if constexpr (requires { leaf.prefetch(std::uint32_t{}); }) {
            for (int m = mask; m; m &= m - 1) {
              const int i = __builtin_ctz(static_cast<unsigned>(m));
              if (n.count[i]) leaf.prefetch(n.child[i]);
            }
          }
          wide_push<Query == BvhQuery::closest>(n, nodes, mask, t, stack, top);
          e = stack[--top];
        }
        continue;
      }
    }
    do {
      if (top == 0) return;
      e = stack[--top];
    } while (Query == BvhQuery::closest && !(e.t <= tmax_cur));
  }
}


#pragma once
/// The table behind a set of generators (families.cpp's families, knobs.cpp's knobs): rows of a
/// described item (with a `name`) and the function that makes its cases, the items alone in table
/// order, lookup by name, and the function of an item.
#include <initializer_list>
#include <string_view>
#include <vector>

namespace rayproof::gen::detail {

template <class Item, class Fn>
struct GenTable {
  struct Row {
    Item item;
    Fn fn;
  };
  std::vector<Row> rows;
  std::vector<Item> items;  ///< rows' items, in table order

  GenTable(std::initializer_list<Row> r) : rows(r) {
    items.reserve(rows.size());
    for (const Row& x : rows) items.push_back(x.item);
  }
  /// The item called `name`, or nullptr.
  [[nodiscard]] const Item* find(std::string_view name) const {
    for (const Item& x : items)
      if (x.name == name) return &x;
    return nullptr;
  }
  /// The function of the item with `item`'s name, or nullptr when the table has none.
  [[nodiscard]] Fn fn_of(const Item& item) const {
    for (const Row& x : rows)
      if (x.item.name == item.name) return x.fn;
    return nullptr;
  }
};

}  // namespace rayproof::gen::detail

#include "domain/ContactSpringStore.hpp"

#include <stdexcept>
#include <utility>

namespace ringdem {

void ContactSpringStore::keep_rows(const std::vector<char>& keep) {
  resize(compact_rows(*this, keep));
}

void ContactSpringStore::drop_released() {
  std::vector<char> keep(size());
  for (std::size_t k = 0; k < size(); ++k)
    keep[k] = carries_state(k);
  keep_rows(keep);
}

void ContactSpringStore::assign_rows(ContactSpringStore&& other) {
  if (other.partner_ != partner_)
    throw std::logic_error("ContactSpringStore: rows of another partner kind");
  *this = std::move(other);
}

}  // namespace ringdem

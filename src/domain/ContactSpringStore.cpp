#include "domain/ContactSpringStore.hpp"

#include <stdexcept>

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

void ContactSpringStore::assign_rows(const ContactSpringStore& other) {
  if (other.partner_ != partner_)
    throw std::logic_error("ContactSpringStore: rows of another partner kind");
  *this = other;
}

}  // namespace ringdem

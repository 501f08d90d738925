/* Reading a protected or private member of a LIGGGHTS class without editing
 * the LIGGGHTS headers or relying on their layout.
 *
 * C++ lets an explicit template instantiation name a private member
 * ([temp.explicit]/12); the instantiation below defines a friend function that
 * returns the member pointer, found by argument-dependent lookup on a tag:
 *
 *   struct FixMapTag { typedef std::map<...> *Modify::*Member; friend Member exposed(FixMapTag); };
 *   template struct ExposeMember<FixMapTag, &Modify::fix_map>;
 *   ... lmp->modify->*exposed(FixMapTag()) ...
 *
 * Reference members cannot be named this way (there is no pointer to them). */
#ifndef POLY_LIGGGHTS_MEMBER_H
#define POLY_LIGGGHTS_MEMBER_H

// In each file's unnamed namespace, where its tags and instantiations go too
// (an explicit instantiation must be in a namespace enclosing the template).
namespace {
template <typename Tag, typename Tag::Member member> struct ExposeMember {
  friend typename Tag::Member exposed(Tag) { return member; }
};
}  // namespace

#endif

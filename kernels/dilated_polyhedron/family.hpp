#pragma once
// The dilated-polyhedron family (book chapter 4): a template per scene shape, a closed triangle
// core in the body's principal frame (centroid at the origin) with its features, normal cones and
// bounding-sphere tree (shapes/dilated_polyhedron.hpp), swept by a sphere of its dilation radius.
// Contacts are the local minima of the distance between cores (pairs.hpp, walls.hpp), several
// per pair, each keyed by the features that make it, their forces weighted by the book's
// averaging over contact points that share a direction (Eq. 4.19's 1 / N_p; SeamSettings).
#include "../../shapes/clump.hpp"
#include "../../shapes/dilated_polyhedron.hpp"
#include "../families/family_rows.hpp"
#include "../families/host_hooks.hpp"
#include "../ragged_table.hpp"
#include "../walls.hpp"

namespace kdem {

struct DilatedContactSettings {
  ConeSlack slack;
  // Contact points whose normals agree within the seam angle share the pair's force in
  // proportion to their overlaps (for equal overlaps, Eq. 4.19's 1 / N_p); reach: unbounded.
  SeamSettings averaging{true, 1e300, 0.8660254};
  // Contacts of one pair (or of a particle and a wall element) closer than `merge` x the
  // smaller dilation radius, whose normals agree within the averaging angle, are one contact: the
  // strongest (cone weight x overlap) is kept. Where corners of two faces coincide, several
  // feature pairs (vertex-vertex, vertex-edge, edge-edge, vertex-face) find the same contact,
  // and how many do changes with every small slide; counted once, the force does not jump.
  double merge = 0.5;
};

// One template's core on the device: flat arrays of the template's rows (pointers into the
// family's ragged tables), with the accessors the contact geometry reads.
struct DeviceCore {
  const CoreVertex* vertices = nullptr;
  const CoreEdge* edges = nullptr;
  const CoreFace* faces = nullptr;
  const Vec3* cones = nullptr;
  const SphereNode* nodes = nullptr;
  int vertex_count = 0, edge_count = 0;
  double radius = 0;
  double caps_reach = -1; // see DilatedCore::caps_reach

  KOKKOS_INLINE_FUNCTION double dilation() const { return radius; }
  KOKKOS_INLINE_FUNCTION double cap_reach() const { return caps_reach; }
  KOKKOS_INLINE_FUNCTION FeatureNumbering numbering() const { return {vertex_count, edge_count}; }
  KOKKOS_INLINE_FUNCTION const CoreVertex& vertex(int k) const { return vertices[k]; }
  KOKKOS_INLINE_FUNCTION const CoreEdge& edge(int k) const { return edges[k]; }
  KOKKOS_INLINE_FUNCTION const CoreFace& face(int k) const { return faces[k]; }
  KOKKOS_INLINE_FUNCTION Vec3 cone(int k) const { return cones[k]; }
  KOKKOS_INLINE_FUNCTION const SphereNode& node(int k) const { return nodes[k]; }
};

struct DilatedPolyhedronWallContact;

struct DilatedPolyhedronFamily {
  static constexpr const char* name = "dilated_polyhedron";
  static constexpr const char* wall_label = "kdem::dilated_polyhedron_wall_contacts";
  static constexpr bool rigid_rotation = true;
  static constexpr bool surface_turns = true;
  // Contact points one body keeps per partner: a pair of two keeps up to 16 (the cap of
  // max_pair_contact_points), against a sphere or a wall element 8 (a box's corners on a plane);
  // where more are found the deepest are kept.
  static constexpr int contact_points = 8;
  static constexpr bool iterative_narrow_phase = false;
  static constexpr bool shape_templates = true; // its scene shapes: `dilated_polyhedron` entries

  struct Table {
    RaggedTable<CoreVertex> vertices;
    RaggedTable<CoreEdge> edges;
    RaggedTable<CoreFace> faces;
    RaggedTable<Vec3> cones;
    RaggedTable<SphereNode> nodes;
    ScalarView dilation;          // m, per template
    ScalarView caps_reach;        // per template: DilatedCore::caps_reach
    ScalarView equivalent_radius; // m, of the sphere of the dilated body's volume, per template
    DilatedContactSettings settings;
  };

  KOKKOS_INLINE_FUNCTION static double equivalent_radius(const Table& t, const ShapeFamilies& s,
                                                         const ParticleViews& p, int i) {
    return t.equivalent_radius(s.template_index(p.shape(i)));
  }

  KOKKOS_INLINE_FUNCTION static DeviceCore core(const Table& t, const ShapeFamilies& s,
                                                const ParticleViews& p, int i) {
    const int k = s.template_index(p.shape(i));
    DeviceCore c;
    c.vertices = t.vertices.values.data() + t.vertices.offsets(k);
    c.edges = t.edges.values.data() + t.edges.offsets(k);
    c.faces = t.faces.values.data() + t.faces.offsets(k);
    c.cones = t.cones.values.data() + t.cones.offsets(k);
    c.nodes = t.nodes.values.data() + t.nodes.offsets(k);
    c.vertex_count = t.vertices.size(k);
    c.edge_count = t.edges.size(k);
    c.radius = t.dilation(k);
    c.caps_reach = t.caps_reach(k);
    return c;
  }

  // Host side (src/dilated_polyhedron_setup.cpp): the core from the scene's mesh, its mass
  // properties and principal frame, bounding radius, output fields and surface, and this table.
  static std::vector<ShapeTemplate> setup_templates(const FamilyShapes& shapes, Table& table);
  static DilatedPolyhedronWallContact wall_contact(const Table& t, const ShapeFamilies& s,
                                                   const WallElements& elements,
                                                   const ParticleViews& p);
};

// Keeps the deepest K contacts found, and weights them (the book's averaging).
template <int K> struct DeepestContacts {
  int count = 0;
  int missed = 0;
  double merge_distance = 0; // see DilatedContactSettings::merge
  double merge_cosine = 1;
  FeatureContact contact[K];

  DeepestContacts() = default;
  // With the settings' merging, for bodies whose smaller dilation radius is `radius`.
  KOKKOS_INLINE_FUNCTION DeepestContacts(const DilatedContactSettings& s, double radius)
      : merge_distance(s.merge * radius), merge_cosine(s.averaging.cos_angle) {}

  KOKKOS_INLINE_FUNCTION static double strength(const FeatureContact& c) {
    return c.cone_weight * c.overlap;
  }

  // The contact already kept that c is one with, or -1.
  KOKKOS_INLINE_FUNCTION int same_as(const FeatureContact& c) const {
    for (int m = 0; m < count; ++m)
      if (norm2(c.point - contact[m].point) < merge_distance * merge_distance &&
          dot(c.normal, contact[m].normal) > merge_cosine)
        return m;
    return -1;
  }

  KOKKOS_INLINE_FUNCTION void add(const FeatureContact& c) {
    if (merge_distance > 0) {
      const int same = same_as(c);
      if (same >= 0) {
        if (strength(c) > strength(contact[same]))
          contact[same] = c;
        return;
      }
    }
    if (count < K) {
      contact[count++] = c;
      return;
    }
    ++missed;
    int shallowest = 0;
    for (int m = 1; m < K; ++m)
      if (contact[m].overlap < contact[shallowest].overlap)
        shallowest = m;
    if (c.overlap > contact[shallowest].overlap)
      contact[shallowest] = c;
  }

  // weight(c) of each contact: its cone weight times its share among the contacts whose normals
  // agree with its own, shared by overlap times cone weight (a contact fading out of its cone
  // gives its share up as it fades).
  template <class SetWeight>
  KOKKOS_INLINE_FUNCTION void weights(const SeamSettings& averaging,
                                      const SetWeight& set_weight) const {
    ContactGeometry g[K];
    for (int c = 0; c < count; ++c)
      g[c] = ContactGeometry{true, contact[c].cone_weight * contact[c].overlap, contact[c].normal,
                             contact[c].point};
    seam_weights(
        count, [&](int c) -> const ContactGeometry& { return g[c]; }, [](int) { return 1.0; },
        averaging, [&](int c, double w) { set_weight(c, contact[c].cone_weight * w); });
  }
};

} // namespace kdem

#include <deal.II/base/utilities.h>

#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_in.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/manifold.h>
#include <deal.II/grid/manifold_lib.h>

#include <contact-stefan/core/common.h>
#include <contact-stefan/core/dipping_interface.h>
#include <contact-stefan/mesh/mesh.h>
#include <contact-stefan/mesh/mesh_adaptation.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <vector>

namespace ContactStefan
{
  namespace
  {
    // The mortar interfaces: (body k, body l) -> (body k's side id, body l's).
    // Between the two sides of one of them nodes need not match.
    using MortarPairs =
      std::map<std::pair<unsigned int, unsigned int>, std::array<unsigned int, 2>>;

    // Per vertex, the mortar interfaces (their index in `pairs`) on whose
    // sides it lies: on a boundary face of body k with k's side id, or of
    // body l with l's.
    std::vector<std::set<unsigned int>> mortar_side_tags(const Triangulation<2> &mesh,
                                                         const MortarPairs      &pairs)
    {
      std::vector<std::set<unsigned int>> tags(pairs.empty() ? 0 : mesh.n_vertices());
      if (pairs.empty())
        return tags;
      for (const auto &cell : mesh.active_cell_iterators())
        for (const unsigned int f : cell->face_indices())
          if (cell->at_boundary(f))
            {
              unsigned int index = 0;
              for (const auto &[pair, ids] : pairs)
                {
                  if ((cell->material_id() == pair.first &&
                       cell->face(f)->boundary_id() == ids[0]) ||
                      (cell->material_id() == pair.second &&
                       cell->face(f)->boundary_id() == ids[1]))
                    for (unsigned int v = 0; v < 2; ++v)
                      tags[cell->face(f)->vertex_index(v)].insert(index);
                  ++index;
                }
            }
      return tags;
    }

    // Whether vertices a and b lie on the same mortar interface's sides.
    bool on_one_mortar_interface(const std::vector<std::set<unsigned int>> &tags,
                                 const unsigned int                         a,
                                 const unsigned int                         b)
    {
      if (tags.empty())
        return false;
      for (const unsigned int t : tags[a])
        if (tags[b].count(t) == 1)
          return true;
      return false;
    }

    std::string point_text(const Point<2> &p)
    {
      std::ostringstream s;
      s << '(' << p[0] << ", " << p[1] << ')';
      return s.str();
    }

    // A Gmsh file, checked before deal.II reads it (its reader loops forever on a
    // section without its end, or on a $MeshFormat that does not match the
    // body): ASCII; every $Section closed by its $EndSection; and for the
    // formats 2.x and 4.x a first $Nodes line of that version's form (2.x: the
    // node count; 4.0: blocks and nodes; 4.1: blocks, nodes, min and max tag)
    // whose node count the file can hold. Format 1 ($NOD) is passed through.
    void check_gmsh_file(const std::string &file)
    {
      const auto fail = [&](const std::string &reason) {
        throw InputError("Geometry/Mesh file",
                         "'" + file + "' is not a readable Gmsh mesh: " + reason);
      };
      std::ifstream     in(file, std::ios::binary);
      const std::string text((std::istreambuf_iterator<char>(in)),
                             std::istreambuf_iterator<char>());
      if (text.find('\0') != std::string::npos)
        fail("it is not a text file (binary Gmsh files are not read; save it as ASCII)");
      std::istringstream lines(text);
      std::string        line, open, version, first_nodes_line;
      bool               first = true, in_nodes = false;
      while (std::getline(lines, line))
        {
          if (!line.empty() && line.back() == '\r')
            line.pop_back();
          if (first && line.rfind("$NOD", 0) == 0)
            return; // format 1: deal.II reads it, nothing here to check
          if (first && line != "$MeshFormat")
            fail("it does not start with $MeshFormat");
          first = false;
          if (in_nodes && first_nodes_line.empty())
            first_nodes_line = line.empty() ? " " : line;
          if (!open.empty() && open == "$MeshFormat" && version.empty())
            version = line;
          if (line.rfind("$End", 0) == 0)
            {
              if (line != "$End" + open.substr(1))
                fail("'" + line.substr(0, 40) + "' without its section (" +
                     (open.empty() ? "none is open" : open + " is open") + ")");
              open.clear();
              in_nodes = false;
            }
          else if (!line.empty() && line[0] == '$')
            {
              if (!open.empty())
                fail("the section " + open + " has no $End" + open.substr(1));
              open     = line.substr(0, 40);
              in_nodes = open == "$Nodes";
            }
        }
      if (!open.empty())
        fail("the section " + open + " has no $End" + open.substr(1));

      std::istringstream format(version);
      std::string        number, file_type;
      format >> number >> file_type;
      if (file_type != "0")
        fail("not an ASCII file (file type '" + file_type.substr(0, 10) + "')");
      std::istringstream  numbers(first_nodes_line);
      std::vector<double> values;
      for (double v; numbers >> v;)
        values.push_back(v);
      std::size_t expected = 0, count_index = 0;
      if (number.rfind("2", 0) == 0)
        expected = 1, count_index = 0;
      else if (number == "4" || number.rfind("4.0", 0) == 0)
        expected = 2, count_index = 1;
      else if (number.rfind("4.1", 0) == 0)
        expected = 4, count_index = 1;
      else
        fail("format version '" + number.substr(0, 20) + "' (2.x, 4.0 and 4.1 are read)");
      if (values.size() != expected)
        fail("the first line of $Nodes has " + std::to_string(values.size()) +
             " numbers, but format " + number + " has " + std::to_string(expected));
      // Each node takes at least a few bytes: a larger count is a corrupt header
      // (and would make the reader allocate for it).
      if (!(values[count_index] >= 0 && values[count_index] <= text.size()))
        fail("$Nodes declares " + std::to_string(values[count_index]) + " nodes in a file of " +
             std::to_string(text.size()) + " bytes");
    }

    // The used vertices of a mesh sorted into a grid of nx x ny buckets h wide
    // from low (a counting sort): bucket k holds sorted[start[k]] ...
    // sorted[start[k + 1] - 1].
    struct VertexBuckets
    {
      VertexBuckets(const std::vector<Point<2>>     &vertices,
                    const std::vector<unsigned int> &used,
                    const Point<2>                  &low,
                    const double                     h,
                    const unsigned int               nx,
                    const unsigned int               ny)
        : vertices(vertices)
        , low(low)
        , h(h)
        , nx(nx)
        , ny(ny)
        , start(nx * ny + 1, 0)
        , sorted(used.size())
      {
        for (const unsigned int v : used)
          ++start[bucket(vertices[v]) + 1];
        for (unsigned int k = 0; k < nx * ny; ++k)
          start[k + 1] += start[k];
        std::vector<unsigned int> next(start.begin(), start.end() - 1);
        for (const unsigned int v : used)
          sorted[next[bucket(vertices[v])]++] = v;
      }

      unsigned int index(const double x, const unsigned int d, const unsigned int n) const
      {
        return static_cast<unsigned int>(std::min<double>(n - 1, std::max(0., (x - low[d]) / h)));
      }

      unsigned int bucket(const Point<2> &p) const
      {
        return index(p[0], 0, nx) + nx * index(p[1], 1, ny);
      }

      // The vertex other than a and b that lies inside the edge from vertex a
      // to vertex b (within near times its length), the one nearest to a;
      // numbers::invalid_unsigned_int if there is none. The edge visits the
      // buckets of its bounding box, or, for a long slanted edge whose box
      // holds many buckets, the 3 x 3 buckets around points at most a bucket
      // apart along it.
      unsigned int vertex_inside_edge(const unsigned int edge_a,
                                      const unsigned int edge_b,
                                      const double       near) const
      {
        const Point<2>     a = vertices[edge_a], b = vertices[edge_b];
        const Tensor<1, 2> d       = b - a;
        const double       length  = d.norm();
        unsigned int       hanging = numbers::invalid_unsigned_int;
        double             nearest = 2;
        const auto         test    = [&](const unsigned int k) {
          for (unsigned int m = start[k]; m < start[k + 1]; ++m)
            {
              const unsigned int v = sorted[m];
              if (v == edge_a || v == edge_b)
                continue;
              const Tensor<1, 2> r        = vertices[v] - a;
              const double       t        = r * d / length / length;
              const double       distance = std::abs(d[0] * r[1] - d[1] * r[0]) / length;
              if (distance <= near * length && t > near && t < 1 - near && t < nearest)
                hanging = v, nearest = t;
            }
        };
        const unsigned int x0        = index(std::min(a[0], b[0]), 0, nx),
                           x1        = index(std::max(a[0], b[0]), 0, nx),
                           y0        = index(std::min(a[1], b[1]), 1, ny),
                           y1        = index(std::max(a[1], b[1]), 1, ny);
        const unsigned int n_samples = static_cast<unsigned int>(std::ceil(length / h)) + 1;
        if (double(x1 - x0 + 1) * (y1 - y0 + 1) <= 9. * n_samples)
          {
            // Bucket edges at round-off distance: one more bucket each way.
            for (unsigned int i = x0 - (x0 > 0); i <= std::min(x1 + 1, nx - 1); ++i)
              for (unsigned int j = y0 - (y0 > 0); j <= std::min(y1 + 1, ny - 1); ++j)
                test(i + nx * j);
          }
        else
          {
            // Samples at most h apart: every point within h of the edge lies
            // in the 3 x 3 buckets around some sample. A bucket may be tested
            // more than once; that finds nothing new.
            for (unsigned int s = 0; s < n_samples; ++s)
              {
                const Point<2>     p = a + d * (double(s) / (n_samples - 1));
                const unsigned int i = index(p[0], 0, nx), j = index(p[1], 1, ny);
                for (unsigned int ii = i - (i > 0); ii <= std::min(i + 1, nx - 1); ++ii)
                  for (unsigned int jj = j - (j > 0); jj <= std::min(j + 1, ny - 1); ++jj)
                    test(ii + nx * jj);
              }
          }
        return hanging;
      }

      const std::vector<Point<2>> &vertices;
      const Point<2>               low;
      const double                 h;
      const unsigned int           nx, ny;
      std::vector<unsigned int>    start, sorted;
    };

    // A coarse mesh must be conforming: no vertex may lie inside an edge. deal.II
    // accepts a node that hangs on a neighbour's edge (a T-junction) and makes
    // the long edge and the two short ones boundary faces: the cells are cut
    // apart there, the heat does not cross and the bodies do not touch, and
    // the run ends with exit 0 and a wrong result. Between two bodies the same
    // happens to a non-matching interface (the bodies share the nodes of their
    // interfaces; nothing here pairs a node with a point inside an edge), so it
    // is refused alike, with its own message.
    //
    // The used vertices are sorted into a grid of buckets about the mean edge
    // length wide (coarser if the mesh's bounding box would need more than a
    // few buckets per vertex). Each edge visits the buckets of its bounding box,
    // or, for a long slanted edge whose box holds many buckets, the 3 x 3
    // buckets around points at most a bucket apart along it: linear in the
    // size of the mesh unless its edges differ in length by orders of magnitude.
    void check_conforming(const Triangulation<2>                    &mesh,
                          const std::string                         &file,
                          const double                               near,
                          const std::vector<std::set<unsigned int>> &mortar_tags)
    {
      const std::vector<Point<2>> &vertices = mesh.get_vertices();
      const std::vector<bool>     &is_used  = mesh.get_used_vertices();
      struct Edge
      {
        unsigned int       a, b;
        types::material_id body;
      };
      std::vector<Edge> edges;
      double            total_length = 0;
      for (const auto &cell : mesh.active_cell_iterators())
        for (const unsigned int f : cell->face_indices())
          // Each interior face once, from the cell of lower index.
          if (cell->at_boundary(f) || cell->index() < cell->neighbor_index(f))
            {
              edges.push_back({cell->face(f)->vertex_index(0),
                               cell->face(f)->vertex_index(1),
                               cell->material_id()});
              total_length += cell->face(f)->measure();
            }
      std::vector<unsigned int> used;
      Point<2> low(std::numeric_limits<double>::max(), std::numeric_limits<double>::max()),
        high = -low;
      for (unsigned int i = 0; i < vertices.size(); ++i)
        if (is_used[i])
          {
            used.push_back(i);
            for (unsigned int d = 0; d < 2; ++d)
              low[d]  = std::min(low[d], vertices[i][d]),
              high[d] = std::max(high[d], vertices[i][d]);
          }
      if (edges.empty() || used.empty())
        return;
      // Coordinates of 1e308 overflow the lengths: such a mesh (refused or
      // run elsewhere) is not checked here.
      double h = total_length / edges.size();
      if (!(h > 0) || !std::isfinite(total_length) || !std::isfinite((high - low).norm()))
        return;
      const double max_buckets = 4. * used.size() + 64;
      const auto   n_buckets   = [&](const unsigned int d) {
        return std::floor((high[d] - low[d]) / h) + 1;
      };
      if (n_buckets(0) * n_buckets(1) > max_buckets)
        h *= std::sqrt(n_buckets(0) * n_buckets(1) / max_buckets) * 1.01;
      const VertexBuckets buckets(vertices, used, low, h, n_buckets(0), n_buckets(1));

      for (const Edge &edge : edges)
        {
          const unsigned int hanging = buckets.vertex_inside_edge(edge.a, edge.b, near);
          if (hanging == numbers::invalid_unsigned_int)
            continue;
          const Point<2> a = vertices[edge.a], b = vertices[edge.b];
          // The bodies of the cells around the hanging node.
          std::set<types::material_id> bodies;
          for (const auto &cell : mesh.active_cell_iterators())
            for (const unsigned int v : cell->vertex_indices())
              if (cell->vertex_index(v) == hanging)
                bodies.insert(cell->material_id());
          const std::string where = "'" + file + "': the node " + point_text(vertices[hanging]) +
                                    " lies inside the edge from " + point_text(a) + " to " +
                                    point_text(b) + " of body " + std::to_string(edge.body);
          // Between the two sides of a mortar interface nodes need not match:
          // the node and the edge on the sides of one mortar interface.
          if (bodies.size() == 1 && bodies.count(edge.body) == 0 &&
              on_one_mortar_interface(mortar_tags, hanging, edge.a) &&
              on_one_mortar_interface(mortar_tags, hanging, edge.b))
            continue;
          if (bodies.count(edge.body) == 1)
            throw InputError("Geometry/Mesh file",
                             where + ": a T-junction (hanging node); the mesh must be conforming, "
                                     "every edge shared whole by the cells on both sides");
          throw InputError("Geometry/Mesh file",
                           where + ", a node of body " + std::to_string(*bodies.begin()) +
                             ": a non-matching interface (the bodies must share the nodes of "
                             "their interfaces)");
        }
    }

    // A Gmsh mesh must be a valid Q1 mesh: every cell's bilinear map has a
    // positive Jacobian determinant at its four vertices (a negative one at all
    // four is an inverted cell, mixed signs a self-overlapping "bow-tie" cell),
    // and no two vertices that cells use coincide (the mesh would be cut there:
    // bodies must share the nodes of their interfaces). One line names the file
    // and the first bad cell.
    void check_mesh(const Triangulation<2> &mesh,
                    const std::string      &file,
                    const MortarPairs      &mortar_pairs = {})
    {
      // Relative to the cell's squared diameter: a geometric zero, far above
      // the round-off of coordinates read from a file, far below any cell a
      // mesh generator makes.
      // Not a parameter: a user has nothing to tune here.
      constexpr double geometric_zero = 1e-12;
      for (const auto &cell : mesh.active_cell_iterators())
        {
          // deal.II's vertex order: 0 (0,0), 1 (1,0), 2 (0,1), 3 (1,1).
          const Point<2> v[4]  = {cell->vertex(0),
                                  cell->vertex(1),
                                  cell->vertex(2),
                                  cell->vertex(3)};
          const auto     cross = [](const Tensor<1, 2> &a, const Tensor<1, 2> &b) {
            return a[0] * b[1] - a[1] * b[0];
          };
          const double J[4] = {cross(v[1] - v[0], v[2] - v[0]),
                               cross(v[1] - v[0], v[3] - v[1]),
                               cross(v[3] - v[2], v[2] - v[0]),
                               cross(v[3] - v[2], v[3] - v[1])};
          const double size = cell->diameter() * cell->diameter();
          for (const double j : J)
            if (!(j > geometric_zero * size))
              throw InputError("Geometry/Mesh file",
                               "'" + file + "': cell " + std::to_string(cell->index()) +
                                 " with vertices " + point_text(v[0]) + " " + point_text(v[1]) +
                                 " " + point_text(v[3]) + " " + point_text(v[2]) + " is " +
                                 (std::max({J[0], J[1], J[2], J[3]}) <= 0 ?
                                    "inverted or degenerate" :
                                    "self-overlapping") +
                                 " (its Jacobian is not positive at every vertex)");
        }
      std::vector<std::pair<Point<2>, unsigned int>> used;
      const std::vector<bool>                       &is_used = mesh.get_used_vertices();
      for (unsigned int i = 0; i < mesh.n_vertices(); ++i)
        if (is_used[i])
          used.emplace_back(mesh.get_vertices()[i], i);
      std::sort(used.begin(), used.end(), [](const auto &a, const auto &b) {
        return a.first[0] < b.first[0] || (a.first[0] == b.first[0] && a.first[1] < b.first[1]);
      });
      // Coincidence and hanging nodes are judged with a coarser zero: a mesh
      // written with 7 or 8 significant digits puts the two copies of a node
      // (or a node on a neighbour's edge) 1e-8 to 1e-7 apart, relative, and
      // must still be refused; no valid mesh has two vertices, or a vertex and
      // an edge it does not end on, within a millionth of its shortest edge.
      constexpr double near = 1e-6;
      double           shortest_edge = std::numeric_limits<double>::max();
      for (const auto &cell : mesh.active_cell_iterators())
        for (const unsigned int f : cell->face_indices())
          shortest_edge = std::min(shortest_edge, cell->face(f)->measure());
      const double apart = near * shortest_edge;
      // The bodies of each vertex and the mortar sides it lies on: the two
      // sides of a mortar interface may put vertices of its two bodies on
      // top of each other (nowhere else).
      const auto                          mortar_tags = mortar_side_tags(mesh, mortar_pairs);
      std::vector<std::set<unsigned int>> bodies_at(mortar_pairs.empty() ? 0 : mesh.n_vertices());
      if (!mortar_pairs.empty())
        for (const auto &cell : mesh.active_cell_iterators())
          for (const unsigned int v : cell->vertex_indices())
            bodies_at[cell->vertex_index(v)].insert(cell->material_id());
      const auto mortar_copies = [&](const unsigned int a, const unsigned int b) {
        if (mortar_pairs.empty() || !on_one_mortar_interface(mortar_tags, a, b))
          return false;
        for (const unsigned int body : bodies_at[a])
          if (bodies_at[b].count(body) == 1)
            return false;
        return true;
      };
      for (unsigned int k = 0; k < used.size(); ++k)
        for (unsigned int m = k + 1;
             m < used.size() && used[m].first[0] - used[k].first[0] <= apart;
             ++m)
          if (used[k].first.distance(used[m].first) <= apart &&
              !mortar_copies(used[k].second, used[m].second))
            throw InputError("Geometry/Mesh file",
                             "'" + file + "': vertices " + std::to_string(used[k].second) +
                               " and " + std::to_string(used[m].second) + " coincide at " +
                               point_text(used[k].first) +
                               ": the mesh is cut there (bodies must share their interface "
                               "nodes)");
      check_conforming(mesh, file, near, mortar_tags);
    }
  } // namespace



  namespace
  {
    // The manifold of the disk in ring's circles (make_disk_in_ring).
    constexpr types::manifold_id circles_manifold_id = 2;

    // doc/benchmarks.md T4's geometry: a quarter disk of radius b (body 0) made of a
    // square core [0, b/2]^2 with n x n cells and two blocks of n x n cells
    // between the core's outer edges and the arc, interpolated linearly along
    // straight lines to arc points at equal angles; around it a quarter ring
    // b < r < c (body 1) of 2n x m cells on the same angles. Every node on a
    // circle lies exactly on it, and the two bodies share the nodes of r = b.
    // With a > 0 the ring has a cells along its arcs instead and nodes of its
    // own on r = b (the two sides of a mortar interface, doc/contact.md):
    // boundary ids 3 (the disk's arc) and 4 (the ring's inner arc).
    void make_disk_in_ring(Triangulation<2> &coarse,
                           const double      b,
                           const double      c,
                           const unsigned    n,
                           const unsigned    m,
                           const unsigned    a)
    {
      std::vector<Point<2>>                                   vertices;
      std::map<std::pair<long long, long long>, unsigned int> index_of;
      const double                                            snap   = 1e-12 * c;
      // (A ring meshed on its own keeps its nodes apart from the disk's.)
      long long  offset = 0;
      const auto vertex = [&](const Point<2> &p) {
        const std::pair<long long, long long> key{std::llround(p[0] / snap) + offset,
                                                  std::llround(p[1] / snap)};
        const auto [it, added] = index_of.emplace(key, vertices.size());
        if (added)
          vertices.push_back(p);
        return it->second;
      };
      const double s = 0.5 * b, quarter = numbers::PI / 4;
      // On the axes exactly: cos(pi/2) is 6e-17, and a boundary face that is
      // not exactly vertical would give its roller a normal with a spurious
      // second component.
      const auto arc = [&](const double r, const double angle) {
        const double x = r * std::cos(angle), y = r * std::sin(angle);
        return Point<2>(std::abs(x) < 1e-14 * r ? 0. : x, std::abs(y) < 1e-14 * r ? 0. : y);
      };
      std::vector<CellData<2>> cells;
      const auto add = [&](const std::array<Point<2>, 4> &p, const types::material_id body) {
        CellData<2> cell;
        for (unsigned int v = 0; v < 4; ++v)
          cell.vertices[v] = vertex(p[v]);
        cell.material_id = body;
        cells.push_back(cell);
      };
      // Core.
      const auto core = [&](const unsigned i, const unsigned j) {
        return Point<2>(i * s / n, j * s / n);
      };
      for (unsigned int j = 0; j < n; ++j)
        for (unsigned int i = 0; i < n; ++i)
          add({{core(i, j), core(i + 1, j), core(i, j + 1), core(i + 1, j + 1)}}, 0);
      // The block right of the core (k outward, j counter-clockwise) and the one
      // above it (i along x, k outward).
      const auto right = [&](const unsigned k, const unsigned j) {
        const double t = double(k) / n;
        return Point<2>((1 - t) * core(n, j) + t * arc(b, j * quarter / n));
      };
      const auto top = [&](const unsigned i, const unsigned k) {
        const double t = double(k) / n;
        return Point<2>((1 - t) * core(i, n) + t * arc(b, 2 * quarter - i * quarter / n));
      };
      for (unsigned int k = 0; k < n; ++k)
        for (unsigned int j = 0; j < n; ++j)
          {
            add({{right(k, j), right(k + 1, j), right(k, j + 1), right(k + 1, j + 1)}}, 0);
            add({{top(j, k), top(j + 1, k), top(j, k + 1), top(j + 1, k + 1)}}, 0);
          }
      // Ring (l outward, a counter-clockwise).
      const unsigned int n_arc = a > 0 ? a : 2 * n;
      const auto         ring  = [&](const unsigned l, const unsigned k) {
        return arc(b + l * (c - b) / m, k * 2 * quarter / n_arc);
      };
      if (a > 0)
        offset = 4 * std::llround(c / snap) + 4;
      for (unsigned int l = 0; l < m; ++l)
        for (unsigned int k = 0; k < n_arc; ++k)
          add({{ring(l, k), ring(l + 1, k), ring(l, k + 1), ring(l + 1, k + 1)}}, 1);

      GridTools::consistently_order_cells(cells);
      coarse.create_triangulation(vertices, cells, SubCellData());
      for (const auto &cell : coarse.active_cell_iterators())
        for (const auto &face : cell->face_iterators())
          if (face->at_boundary())
            {
              const Point<2> x = face->center();
              face->set_boundary_id(std::abs(x[0]) < 1e-10 * c ? 0 :
                                    std::abs(x[1]) < 1e-10 * c ? 1 :
                                    x.norm() > 0.5 * (b + c)   ? 2 :
                                    cell->material_id() == 0   ? 3 :
                                                                 4);
            }
      // The circles stay circles when refined: the ring (cells and faces) and
      // the disk's faces on r = b follow a polar manifold about the origin, so
      // a refined arc puts its new node on its circle (a radial face's new node
      // is its midpoint); the disk's cells keep the flat manifold, whose
      // transfinite interpolation takes a refined cell's centre from its faces.
      // (The ring's radial faces stay flat: their midpoints are the straight
      // ones, and those on the axes stay exactly on them, as the rollers need.)
      for (const auto &cell : coarse.active_cell_iterators())
        if (cell->material_id() == 1)
          {
            cell->set_all_manifold_ids(circles_manifold_id);
            for (const auto &face : cell->face_iterators())
              if (std::abs(face->vertex(0).norm() - face->vertex(1).norm()) > 1e-10 * c)
                face->set_manifold_id(numbers::flat_manifold_id);
          }
        else
          for (const auto &face : cell->face_iterators())
            if (std::abs(face->vertex(0).norm() - b) < 1e-10 * c &&
                std::abs(face->vertex(1).norm() - b) < 1e-10 * c)
              face->set_manifold_id(circles_manifold_id);
      coarse.set_manifold(circles_manifold_id, PolarManifold<2>(Point<2>()));
    }

    // The manifold of a bent dipping interface: a new point on a face of the
    // interface (a refined face's midpoint) is the curve's point at the
    // weighted mean height of the face's points. The cells keep the flat
    // manifold: deal.II places a refined cell's centre by transfinite
    // interpolation from its faces' new points, so the cells next to the
    // interface follow it.
    constexpr types::manifold_id interface_manifold_id = 1;

    class DippingInterfaceManifold : public Manifold<2>
    {
    public:
      explicit DippingInterfaceManifold(std::shared_ptr<const DippingInterface> interface)
        : interface(std::move(interface))
      {}
      std::unique_ptr<Manifold<2>> clone() const override
      {
        return std::make_unique<DippingInterfaceManifold>(interface);
      }
      Point<2> get_new_point(const ArrayView<const Point<2>> &points,
                             const ArrayView<const double>   &weights) const override
      {
        double y = 0;
        for (unsigned int i = 0; i < points.size(); ++i)
          y += weights[i] * points[i][1];
        return Point<2>(interface->x_at(y), y);
      }
      Point<2> project_to_manifold(const ArrayView<const Point<2>> &,
                                   const Point<2> &candidate) const override
      {
        return Point<2>(interface->x_at(candidate[1]), candidate[1]);
      }

    private:
      std::shared_ptr<const DippingInterface> interface;
    };



    // The rectangle [x0, x1] x [y0, y1] cut by an interface from (xt, y1)
    // down to y0, dipping at `dip` degrees towards +x (straight, or steepening
    // to dip_at_base at y0: dipping_interface_x). Each row of
    // nodes is spaced uniformly on both sides of the interface, so the interface
    // is a mesh line; the nx columns are split in proportion to the bodies' mean
    // widths. Body 0 lies left of/below the interface, body 1 right of/above it.
    void make_dipping_interface(Triangulation<2>       &coarse,
                                const Point<2>         &lower_left,
                                const Point<2>         &upper_right,
                                const DippingInterface &interface,
                                const unsigned          nx)
    {
      const double x0 = lower_left[0], x1 = upper_right[0];
      const double y0 = lower_left[1], y1 = upper_right[1];
      // The interface's node on each coarse row, bottom to top.
      const std::vector<Point<2>> &rows      = interface.nodes();
      const unsigned int           ny        = rows.size() - 1;
      const auto                   fault_x   = [&](const double y) { return interface.x_at(y); };
      const double       mean_left = 0.5 * (fault_x(y1) + fault_x(y0)) - x0;
      const long         share     = std::lround(nx * mean_left / (x1 - x0));
      const unsigned int n_left =
        static_cast<unsigned int>(std::min<long>(nx - 1, std::max<long>(1, share)));
      // Refuse cells that would be slivers: the widest and narrowest columns
      // (at the top or the bottom of each side) against the row height.
      const double height = (y1 - y0) / ny;
      double       aspect = 1;
      for (const double width : {(fault_x(y1) - x0) / n_left,
                                 (fault_x(y0) - x0) / n_left,
                                 (x1 - fault_x(y1)) / (nx - n_left),
                                 (x1 - fault_x(y0)) / (nx - n_left)})
        aspect = std::max({aspect, width / height, height / width});
      // A sanity limit on the generator's output, not a physics parameter: Q1
      // cells much longer than wide make the enthalpy step's conductivity
      // matrix far from an M-matrix (Geometry/Subdivisions) and the contact
      // normals of the interface meaningless.
      constexpr double max_aspect = 10;
      if (aspect > max_aspect)
        throw InputError("Geometry/Subdivisions",
                         "the dipping-interface mesh would have cells with an aspect ratio of " +
                           number(aspect) + " (more than " + number(max_aspect) +
                           "): change Subdivisions, Interface top x or Interface dip");
      // A bent interface: refinement moves each new node of the interface from
      // its chord's midpoint to the curve (the manifold below). Where that
      // offset is a sizeable part of the cells beside it, the refined cells next
      // to the interface would be squashed or inverted. Each refinement divides
      // the offset by 4 and the cells' width by 2, so the coarse rows decide.
      // (A limit on the generator's output, like max_aspect, not a physics
      // parameter: a quarter of the width keeps a refined cell beside the
      // interface at least half as wide on its narrow side as on its other.)
      constexpr double max_offset = 0.25;
      if (interface.curved())
        for (unsigned int j = 0; j < ny; ++j)
          {
            const double y     = 0.5 * (rows[j][1] + rows[j + 1][1]);
            const double chord = 0.5 * (rows[j][0] + rows[j + 1][0]);
            const double off   = std::abs(interface.x_at(y) - chord);
            const double width = std::min((chord - x0) / n_left, (x1 - chord) / (nx - n_left));
            if (off > max_offset * width)
              throw InputError("Geometry/Subdivisions",
                               "the bent interface lies " + number(off) +
                                 " m off its chord in coarse row " + std::to_string(j + 1) +
                                 " of " + std::to_string(ny) +
                                 ", more than a quarter of the width of the cells beside it (" +
                                 number(width) +
                                 " m): refined cells would be squashed or inverted; use more "
                                 "rows (the second value)");
          }
      std::vector<Point<2>> vertices;
      for (unsigned int j = 0; j <= ny; ++j)
        {
          const double y  = rows[j][1];
          const double xf = rows[j][0];
          for (unsigned int i = 0; i <= nx; ++i)
            {
              const double x = i <= n_left ? x0 + i * (xf - x0) / n_left :
                                             xf + (i - n_left) * (x1 - xf) / (nx - n_left);
              vertices.emplace_back(i == nx ? x1 : x, y);
            }
        }
      std::vector<CellData<2>> cells;
      for (unsigned int j = 0; j < ny; ++j)
        for (unsigned int i = 0; i < nx; ++i)
          {
            CellData<2> cell;
            cell.vertices[0] = j * (nx + 1) + i;
            cell.vertices[1] = j * (nx + 1) + i + 1;
            cell.vertices[2] = (j + 1) * (nx + 1) + i;
            cell.vertices[3] = (j + 1) * (nx + 1) + i + 1;
            cell.material_id = i < n_left ? 0 : 1;
            cells.push_back(cell);
          }
      coarse.create_triangulation(vertices, cells, SubCellData());
      const double tolerance = 1e-10 * std::max(x1 - x0, y1 - y0);
      for (const auto &cell : coarse.active_cell_iterators())
        for (const auto &face : cell->face_iterators())
          if (face->at_boundary())
            {
              const Point<2> c = face->center();
              face->set_boundary_id(std::abs(c[0] - x0) < tolerance ? 0 :
                                    std::abs(c[0] - x1) < tolerance ? 1 :
                                    std::abs(c[1] - y0) < tolerance ? 2 :
                                                                      3);
            }
      // A bent interface: its faces follow the curve when refined.
      if (interface.curved())
        {
          for (const auto &cell : coarse.active_cell_iterators())
            if (cell->material_id() == 0)
              for (const unsigned int f : cell->face_indices())
                if (!cell->at_boundary(f) && cell->neighbor(f)->material_id() == 1)
                  cell->face(f)->set_manifold_id(interface_manifold_id);
          coarse.set_manifold(interface_manifold_id,
                              DippingInterfaceManifold(
                                std::make_shared<const DippingInterface>(interface)));
        }
    }



    // A mesh that would exceed the cell cap is refused before it is built.
    void check_cell_count(const double                  cells,
                          const Parameters::Refinement &refinement,
                          const std::string            &parameter)
    {
      if (cells > refinement.max_cells)
        throw InputError(parameter,
                         "the mesh would have " + std::to_string(cells) +
                           " cells, more than 'Mesh refinement/Max cells' = " +
                           std::to_string(refinement.max_cells));
    }



    // The coarse mesh of the scene: a rectangle (optionally in horizontal
    // layers, one body each), the disk in a ring, a rectangle cut by a dipping
    // interface, or a Gmsh file.
    template <int dim>
    void make_coarse_mesh(const Parameters::Geometry                &g,
                          const Parameters::Refinement              &refinement,
                          const MortarPairs                         &mortar_pairs,
                          parallel::distributed::Triangulation<dim> &triangulation)
    {
      if (g.mesh_type == Parameters::Geometry::MeshType::rectangle)
        {
          GridGenerator::subdivided_hyper_rectangle(triangulation,
                                                    {g.subdivisions[0], g.subdivisions[1]},
                                                    g.lower_left,
                                                    g.upper_right,
                                                    true);
          for (const auto &cell : triangulation.active_cell_iterators())
            {
              unsigned int layer = 0;
              for (const double y : g.layer_interfaces)
                {
                  const double lo = cell->vertex(0)[1], hi = cell->vertex(3)[1];
                  const double tolerance = 1e-10 * (hi - lo);
                  if (y > lo + tolerance && y < hi - tolerance)
                    throw InputError(
                      "Geometry/Layer interfaces",
                      "y = " + std::to_string(y) +
                        " does not lie on a line of the coarse mesh (see Subdivisions)");
                  if (cell->center()[1] > y)
                    ++layer;
                }
              cell->set_material_id(layer);
            }
        }
      else if (g.mesh_type == Parameters::Geometry::MeshType::dipping_interface)
        {
          const double cells = double(g.subdivisions[0]) * g.subdivisions[1] *
                               std::pow(4., refinement.initial_global_refinements);
          check_cell_count(cells, refinement, "Geometry/Subdivisions");
          Triangulation<dim> coarse;
          const auto         interface = std::make_shared<const DippingInterface>(g);
          make_dipping_interface(
            coarse, g.lower_left, g.upper_right, *interface, g.subdivisions[0]);
          check_mesh(coarse, "the dipping-interface mesh");
          // (copy_triangulation() clones the manifold with the manifold ids.)
          triangulation.copy_triangulation(coarse);
        }
      else if (g.mesh_type == Parameters::Geometry::MeshType::disk_in_ring)
        {
          const double       n = g.subdivisions[0], m = g.subdivisions[1];
          const unsigned int a     = g.subdivisions.size() > 2 ? g.subdivisions[2] : 0;
          const double       cells = (3 * n * n + (a > 0 ? a : 2 * n) * m) *
                               std::pow(4., refinement.initial_global_refinements);
          check_cell_count(cells, refinement, "Geometry/Subdivisions");
          Triangulation<dim> coarse;
          make_disk_in_ring(
            coarse, g.inner_radius, g.outer_radius, g.subdivisions[0], g.subdivisions[1], a);
          check_mesh(coarse, "the disk-in-ring mesh", mortar_pairs);
          triangulation.copy_triangulation(coarse);
        }
      else
        {
          // Read into a serial coarse mesh first and check it there: p4est and the
          // hp constraints would crash on an inverted or self-overlapping cell.
          check_gmsh_file(g.mesh_file);
          Triangulation<dim> coarse;
          GridIn<dim>        grid_in;
          grid_in.attach_triangulation(coarse);
          std::ifstream in(g.mesh_file);
          try
            {
              grid_in.read_msh(in);
            }
          catch (const std::exception &e)
            {
              throw InputError("Geometry/Mesh file",
                               "'" + g.mesh_file + "' is not a readable Gmsh mesh (" +
                                 one_line(e.what()).substr(0, 120) + ")");
            }
          check_mesh(coarse, g.mesh_file, mortar_pairs);
          const double cells =
            coarse.n_active_cells() * std::pow(4., refinement.initial_global_refinements);
          check_cell_count(cells, refinement, "Mesh refinement/Initial global refinements");
          triangulation.copy_triangulation(coarse);
        }
    }



    // Every material id must be a body and every thermal boundary must exist.
    // Collective.
    template <int dim>
    void check_ids_in_mesh(const SceneParameters                           &prm,
                           const parallel::distributed::Triangulation<dim> &triangulation)
    {
      const MPI_Comm         mpi_communicator = triangulation.get_communicator();
      std::set<unsigned int> materials, boundaries;
      // 65536 body + boundary id of every boundary face: the sides
      // of mortar interfaces.
      std::set<unsigned int> sides;
      for (const auto &cell : triangulation.active_cell_iterators())
        if (!cell->is_artificial())
          {
            materials.insert(cell->material_id());
            for (const auto &face : cell->face_iterators())
              if (face->at_boundary())
                {
                  boundaries.insert(face->boundary_id());
                  sides.insert(65536 * cell->material_id() + face->boundary_id());
                }
          }
      materials  = Utilities::MPI::compute_set_union(materials, mpi_communicator);
      boundaries = Utilities::MPI::compute_set_union(boundaries, mpi_communicator);
      sides      = Utilities::MPI::compute_set_union(sides, mpi_communicator);
      for (const auto &[pair, law] : prm.interface_pairs)
        if (law.discretisation == Parameters::InterfacePair::Discretisation::mortar)
          for (unsigned int side = 0; side < 2; ++side)
            {
              const unsigned int body = side == 0 ? pair.first : pair.second;
              const unsigned int id   = law.mortar_boundaries[side];
              if (sides.count(65536 * body + id) == 0)
                throw InputError("Contact/" +
                                   Parameters::InterfacePair::section(pair.first, pair.second) +
                                   "/Mortar boundaries",
                                 "body " + std::to_string(body) + " has no boundary face with id " +
                                   std::to_string(id) + " in the mesh");
            }
      for (const unsigned int m : materials)
        if (prm.materials.count(m) == 0)
          throw InputError("Bodies/Body ids",
                           "the mesh has body (material) id " + std::to_string(m) +
                             ", which is not listed");
      for (const unsigned int b : prm.body_ids)
        if (materials.count(b) == 0)
          throw InputError("Bodies/Body ids",
                           "body " + std::to_string(b) + " does not occur in the mesh");
      for (const auto &[id, bc] : prm.thermal_boundaries)
        if (boundaries.count(id) == 0)
          throw InputError("Boundary conditions/Thermal boundaries",
                           "boundary id " + std::to_string(id) + " does not occur in the mesh");
      for (const auto &[id, bc] : prm.mechanical_boundaries)
        if (boundaries.count(id) == 0)
          throw InputError("Boundary conditions/Mechanical boundaries",
                           "boundary id " + std::to_string(id) + " does not occur in the mesh");
    }



    // 'Pre-refinement steps' rounds of refining the cells within 'Pre-refinement
    // radius' of the centre, both sides of a contact interface alike. Collective.
    template <int dim>
    void prerefine(const SceneParameters                     &prm,
                   const Parameters::Refinement              &r,
                   parallel::distributed::Triangulation<dim> &triangulation)
    {
      const MPI_Comm mpi_communicator = triangulation.get_communicator();
      for (unsigned int step = 0; step < r.prerefinement_steps; ++step)
        {
          for (const auto &cell : triangulation.active_cell_iterators())
            if (cell->is_locally_owned() && cell->center().distance(r.prerefinement_center) <
                                              r.prerefinement_radius + 0.5 * cell->diameter())
              cell->set_refine_flag();
          // Both sides of a contact interface are refined alike (the
          // node-to-node pairs need the same vertices on both sides).
          if (prm.physics.mechanics)
            make_interfaces_conforming(triangulation);
          // Each flagged cell becomes four: refuse before the cells are built.
          unsigned int flagged = 0;
          for (const auto &cell : triangulation.active_cell_iterators())
            flagged += cell->is_locally_owned() && cell->refine_flag_set();
          const double cells = triangulation.n_global_active_cells() +
                               3. * Utilities::MPI::sum(flagged, mpi_communicator);
          if (cells > r.max_cells)
            throw InputError("Mesh refinement/Pre-refinement steps",
                             "pre-refinement step " + std::to_string(step + 1) + " would make " +
                               std::to_string(cells) +
                               " cells, more than 'Mesh refinement/Max cells' = " +
                               std::to_string(r.max_cells));
          triangulation.execute_coarsening_and_refinement();
          // p4est's 2:1 balance may have refined one side of an interface.
          for (unsigned int round = 0;
               prm.physics.mechanics && flag_nonconforming_interface_cells(triangulation) > 0;
               ++round)
            {
              if (round == 10)
                throw std::runtime_error("an interface between bodies is still refined "
                                         "differently on its two sides after 10 repairs");
              make_interfaces_conforming(triangulation);
              triangulation.execute_coarsening_and_refinement();
            }
        }
    }
  } // namespace



  // The mesh: a rectangle (optionally in horizontal layers, one body each), the
  // disk in a ring, a rectangle cut by a dipping interface, or a Gmsh file. Body and boundary ids
  // in the mesh are checked against the parameter file here, before any time step runs.
  template <int dim>
  void make_mesh(const SceneParameters                     &prm,
                 const Parameters::Refinement              &refinement,
                 parallel::distributed::Triangulation<dim> &triangulation,
                 const bool                                 coarse_only)
  {
    assert_two_dimensional<dim>();
    MortarPairs mortar_pairs;
    for (const auto &[pair, law] : prm.interface_pairs)
      if (law.discretisation == Parameters::InterfacePair::Discretisation::mortar)
        mortar_pairs[pair] = law.mortar_boundaries;
    make_coarse_mesh(prm.geometry, refinement, mortar_pairs, triangulation);
    check_ids_in_mesh(prm, triangulation);
    if (coarse_only)
      return;
    triangulation.refine_global(refinement.initial_global_refinements);
    if (refinement.prerefinement_radius > 0)
      prerefine(prm, refinement, triangulation);
  }



  template void make_mesh<2>(const SceneParameters &,
                             const Parameters::Refinement &,
                             parallel::distributed::Triangulation<2> &,
                             const bool);
} // namespace ContactStefan

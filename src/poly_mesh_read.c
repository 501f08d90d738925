/* Surface mesh input: STL (ascii and binary), Wavefront OBJ and OFF.
 *
 * Every reader appends to one growable poly_mesh and reports the first defect
 * with its line number; nothing is validated geometrically here, that is the
 * job of poly_shape_build, which sees all formats alike.
 */
#include "poly_shape.h"
#include "poly_message.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct poly_mesh_builder {
  poly_mesh mesh;
  int vertex_capacity;
  int triangle_capacity;
} poly_mesh_builder;

/* The reader's view of the file: a NUL-terminated copy that lines are cut out of in place. */
typedef struct poly_text {
  char *cursor;
  char *end;
  int line;
  const char *path;
  char *message;
  size_t message_size;
} poly_text;


static int poly_builder_add_vertex(poly_mesh_builder *builder, double x, double y, double z)
{
  poly_mesh *mesh = &builder->mesh;
  if (mesh->num_vertices == builder->vertex_capacity) {
    if (builder->vertex_capacity > INT_MAX / 6) return 0;
    int capacity = builder->vertex_capacity ? 2 * builder->vertex_capacity : 64;
    double *grown = (double *)realloc(mesh->vertices, sizeof(double) * 3 * (size_t)capacity);
    if (!grown) return 0;
    mesh->vertices = grown;
    builder->vertex_capacity = capacity;
  }
  double *v = mesh->vertices + 3 * (size_t)mesh->num_vertices++;
  v[0] = x;
  v[1] = y;
  v[2] = z;
  return 1;
}

static int poly_builder_add_triangle(poly_mesh_builder *builder, int a, int b, int c)
{
  poly_mesh *mesh = &builder->mesh;
  if (mesh->num_triangles == builder->triangle_capacity) {
    if (builder->triangle_capacity > INT_MAX / 6) return 0;
    int capacity = builder->triangle_capacity ? 2 * builder->triangle_capacity : 64;
    int *grown = (int *)realloc(mesh->triangles, sizeof(int) * 3 * (size_t)capacity);
    if (!grown) return 0;
    mesh->triangles = grown;
    builder->triangle_capacity = capacity;
  }
  int *t = mesh->triangles + 3 * (size_t)mesh->num_triangles++;
  t[0] = a;
  t[1] = b;
  t[2] = c;
  return 1;
}

static poly_status poly_text_out_of_memory(poly_text *text)
{
  return poly_fail(text->message, text->message_size, POLY_ERROR_MEMORY,
                        "mesh file '%s' line %d: out of memory", text->path, text->line);
}

/* Cuts the next line out of the buffer (CR/LF stripped) or returns NULL at the end. */
static char *poly_text_next_line(poly_text *text)
{
  if (text->cursor >= text->end) return NULL;
  char *line = text->cursor;
  char *newline = (char *)memchr(line, '\n', (size_t)(text->end - line));
  char *stop = newline ? newline : text->end;
  text->cursor = newline ? newline + 1 : text->end;
  *stop = '\0';
  if (stop > line && stop[-1] == '\r') stop[-1] = '\0';
  text->line++;
  return line;
}

static int poly_is_space(char c)
{
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

/* Returns the next whitespace-separated token, NUL-terminated in place, or NULL. */
static char *poly_next_token(char **cursor)
{
  char *p = *cursor;
  while (*p && poly_is_space(*p)) p++;
  if (!*p) {
    *cursor = p;
    return NULL;
  }
  char *token = p;
  while (*p && !poly_is_space(*p)) p++;
  if (*p) *p++ = '\0';
  *cursor = p;
  return token;
}

static int poly_equal_nocase(const char *a, const char *b)
{
  for (; *a && *b; a++, b++) {
    char x = (*a >= 'A' && *a <= 'Z') ? (char)(*a - 'A' + 'a') : *a;
    char y = (*b >= 'A' && *b <= 'Z') ? (char)(*b - 'A' + 'a') : *b;
    if (x != y) return 0;
  }
  return *a == *b;
}

/* A whole token must be a finite number: "1.5x" or "nan" is a parse error, not 1.5. */
static int poly_parse_double(char **cursor, double *value)
{
  char *token = poly_next_token(cursor);
  if (!token) return 0;
  char *end = NULL;
  errno = 0;
  *value = strtod(token, &end);
  return end != token && *end == '\0' && errno != ERANGE && isfinite(*value);
}

static int poly_parse_vertex(char **cursor, poly_mesh_builder *builder, int *out_of_memory)
{
  double x, y, z;
  *out_of_memory = 0;
  if (!poly_parse_double(cursor, &x) || !poly_parse_double(cursor, &y) ||
      !poly_parse_double(cursor, &z))
    return 0;
  if (!poly_builder_add_vertex(builder, x, y, z)) {
    *out_of_memory = 1;
    return 0;
  }
  return 1;
}

/* Parses a decimal int; `stop` receives the first character after it. */
static int poly_parse_int(const char *token, long *value, char **stop)
{
  errno = 0;
  *value = strtol(token, stop, 10);
  return *stop != token && errno != ERANGE && *value >= INT_MIN && *value <= INT_MAX;
}

/* Polygons are fan-triangulated around their first corner; with the convex or
 * nearly planar polygons that meshers write this keeps the surface. */
static int poly_add_fan(poly_mesh_builder *builder, const int *corners, int count)
{
  for (int i = 1; i + 1 < count; i++)
    if (!poly_builder_add_triangle(builder, corners[0], corners[i], corners[i + 1])) return 0;
  return 1;
}

static int poly_push_corner(int **corners, int *count, int *capacity, int corner)
{
  if (*count == *capacity) {
    if (*capacity > INT_MAX / 4) return 0;
    int grown_capacity = *capacity ? 2 * *capacity : 16;
    int *grown = (int *)realloc(*corners, sizeof(int) * (size_t)grown_capacity);
    if (!grown) return 0;
    *corners = grown;
    *capacity = grown_capacity;
  }
  (*corners)[(*count)++] = corner;
  return 1;
}

/* ------------------------------------------------------------------ STL */

static uint32_t poly_read_u32_le(const unsigned char *p)
{
  return (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) | ((uint32_t)p[3] << 24);
}

static float poly_read_f32_le(const unsigned char *p)
{
  uint32_t bits = poly_read_u32_le(p);
  float value;
  memcpy(&value, &bits, sizeof value);
  return value;
}

static poly_status poly_read_stl_binary(const unsigned char *data, uint32_t count, poly_text *text,
                                        poly_mesh_builder *builder)
{
  if (count > (uint32_t)(INT_MAX / 3))
    return poly_fail(text->message, text->message_size, POLY_ERROR_PARSE,
                          "mesh file '%s': binary STL declares too many triangles (%lu)",
                          text->path, (unsigned long)count);
  for (uint32_t t = 0; t < count; t++) {
    /* Each record: normal (ignored, recomputed from the corners), 3 corners, attribute word. */
    const unsigned char *record = data + 84 + 50 * (size_t)t;
    for (int k = 0; k < 3; k++) {
      const unsigned char *p = record + 12 + 12 * k;
      double x = poly_read_f32_le(p), y = poly_read_f32_le(p + 4), z = poly_read_f32_le(p + 8);
      if (!isfinite(x) || !isfinite(y) || !isfinite(z))
        return poly_fail(text->message, text->message_size, POLY_ERROR_PARSE,
                              "mesh file '%s': binary STL triangle %lu has a non-finite coordinate",
                              text->path, (unsigned long)t + 1);
      if (!poly_builder_add_vertex(builder, x, y, z)) return poly_text_out_of_memory(text);
    }
    int base = 3 * (int)t;
    if (!poly_builder_add_triangle(builder, base, base + 1, base + 2))
      return poly_text_out_of_memory(text);
  }
  return POLY_OK;
}

static poly_status poly_read_stl_ascii(poly_text *text, poly_mesh_builder *builder)
{
  int in_loop = 0, loop_corners = 0, loop_line = 0;
  char *line;
  while ((line = poly_text_next_line(text)) != NULL) {
    char *cursor = line;
    char *keyword = poly_next_token(&cursor);
    if (!keyword || poly_equal_nocase(keyword, "solid") || poly_equal_nocase(keyword, "endsolid") ||
        poly_equal_nocase(keyword, "facet") || poly_equal_nocase(keyword, "endfacet"))
      continue;
    if (poly_equal_nocase(keyword, "outer")) {
      char *loop = poly_next_token(&cursor);
      if (in_loop || !loop || !poly_equal_nocase(loop, "loop")) break;
      in_loop = 1;
      loop_corners = 0;
      loop_line = text->line;
    } else if (poly_equal_nocase(keyword, "vertex")) {
      int out_of_memory;
      if (!in_loop || loop_corners == 3) break;
      if (!poly_parse_vertex(&cursor, builder, &out_of_memory))
        return out_of_memory ? poly_text_out_of_memory(text)
                             : poly_fail(text->message, text->message_size, POLY_ERROR_PARSE,
                                              "mesh file '%s' line %d: vertex needs 3 finite numbers",
                                              text->path, text->line);
      loop_corners++;
    } else if (poly_equal_nocase(keyword, "endloop")) {
      if (!in_loop || loop_corners != 3) break;
      int n = builder->mesh.num_vertices;
      if (!poly_builder_add_triangle(builder, n - 3, n - 2, n - 1))
        return poly_text_out_of_memory(text);
      in_loop = 0;
    } else {
      break;
    }
  }
  if (line)
    return poly_fail(text->message, text->message_size, POLY_ERROR_PARSE,
                          "mesh file '%s' line %d: unexpected '%.40s' in ascii STL (facets need "
                          "'outer loop', 3 'vertex' lines, 'endloop')",
                          text->path, text->line, line);
  if (in_loop)
    return poly_fail(text->message, text->message_size, POLY_ERROR_PARSE,
                          "mesh file '%s' line %d: file ends inside the facet loop opened there",
                          text->path, loop_line);
  return POLY_OK;
}

static poly_status poly_read_stl(char *data, size_t size, poly_text *text, poly_mesh_builder *builder)
{
  const unsigned char *bytes = (const unsigned char *)data;
  /* Binary files may start with "solid" too, so the size rule decides first. */
  if (size >= 84) {
    uint32_t count = poly_read_u32_le(bytes + 80);
    if ((uint64_t)84 + 50 * (uint64_t)count == (uint64_t)size)
      return poly_read_stl_binary(bytes, count, text, builder);
  }
  const char *p = data;
  while (p < data + size && (poly_is_space(*p) || *p == '\n')) p++;
  int looks_ascii = (size_t)(data + size - p) >= 5 && memcmp(p, "solid", 5) == 0 &&
                    memchr(data, '\0', size) == NULL;
  if (looks_ascii) return poly_read_stl_ascii(text, builder);
  if (size < 84)
    return poly_fail(text->message, text->message_size, POLY_ERROR_PARSE,
                          "mesh file '%s': not ascii STL and truncated as binary STL (%lu bytes, "
                          "the header alone needs 84)",
                          text->path, (unsigned long)size);
  uint32_t count = poly_read_u32_le(bytes + 80);
  return poly_fail(text->message, text->message_size, POLY_ERROR_PARSE,
                        "mesh file '%s': binary STL truncated or padded: header declares %lu "
                        "triangles (%llu bytes) but the file has %lu bytes",
                        text->path, (unsigned long)count,
                        (unsigned long long)(84 + 50 * (uint64_t)count), (unsigned long)size);
}

/* ------------------------------------------------------------------ OBJ */

/* OBJ corners are "v", "v/vt", "v//vn" or "v/vt/vn"; only v matters. Negative
 * indices count back from the latest vertex, positive ones may point forward. */
static poly_status poly_read_obj(poly_text *text, poly_mesh_builder *builder)
{
  int *corners = NULL, corner_capacity = 0;
  long highest = 0;
  int highest_line = 0;
  poly_status status = POLY_OK;
  char *line;
  while (status == POLY_OK && (line = poly_text_next_line(text)) != NULL) {
    char *cursor = line;
    char *keyword = poly_next_token(&cursor);
    if (!keyword) continue;
    if (strcmp(keyword, "v") == 0) {
      int out_of_memory;
      if (!poly_parse_vertex(&cursor, builder, &out_of_memory))
        status = out_of_memory ? poly_text_out_of_memory(text)
                               : poly_fail(text->message, text->message_size, POLY_ERROR_PARSE,
                                                "mesh file '%s' line %d: vertex needs 3 finite numbers",
                                                text->path, text->line);
    } else if (strcmp(keyword, "f") == 0) {
      int count = 0;
      char *token;
      while (status == POLY_OK && (token = poly_next_token(&cursor)) != NULL) {
        long index;
        char *stop;
        if (!poly_parse_int(token, &index, &stop) || (*stop != '\0' && *stop != '/') || index == 0) {
          status = poly_fail(text->message, text->message_size, POLY_ERROR_PARSE,
                                  "mesh file '%s' line %d: bad face vertex index '%.40s'",
                                  text->path, text->line, token);
        } else if (index < 0 && -index > builder->mesh.num_vertices) {
          status = poly_fail(text->message, text->message_size, POLY_ERROR_PARSE,
                                  "mesh file '%s' line %d: face references vertex %ld but only %d "
                                  "vertices precede it",
                                  text->path, text->line, index, builder->mesh.num_vertices);
        } else {
          if (index > highest) {
            highest = index;
            highest_line = text->line;
          }
          int corner = index < 0 ? builder->mesh.num_vertices + (int)index : (int)index - 1;
          if (!poly_push_corner(&corners, &count, &corner_capacity, corner))
            status = poly_text_out_of_memory(text);
        }
      }
      if (status == POLY_OK && count < 3)
        status = poly_fail(text->message, text->message_size, POLY_ERROR_PARSE,
                                "mesh file '%s' line %d: face has %d vertices, needs at least 3",
                                text->path, text->line, count);
      if (status == POLY_OK && !poly_add_fan(builder, corners, count))
        status = poly_text_out_of_memory(text);
    }
    /* vt, vn, g, o, s, usemtl, mtllib, l, comments: irrelevant to the solid. */
  }
  free(corners);
  if (status == POLY_OK && highest > builder->mesh.num_vertices)
    status = poly_fail(text->message, text->message_size, POLY_ERROR_PARSE,
                            "mesh file '%s' line %d: face references vertex %ld but the file "
                            "defines only %d vertices",
                            text->path, highest_line, highest, builder->mesh.num_vertices);
  return status;
}

/* ------------------------------------------------------------------ OFF */

/* Next line with content, comments ('#' to end of line) removed. */
static char *poly_off_next_line(poly_text *text)
{
  char *line;
  while ((line = poly_text_next_line(text)) != NULL) {
    char *hash = strchr(line, '#');
    if (hash) *hash = '\0';
    char *p = line;
    while (*p && poly_is_space(*p)) p++;
    if (*p) return line;
  }
  return NULL;
}

static int poly_off_parse_count(char **cursor, long *value)
{
  char *token = poly_next_token(cursor);
  char *stop;
  return token && poly_parse_int(token, value, &stop) && *stop == '\0' && *value >= 0;
}

static poly_status poly_read_off(poly_text *text, poly_mesh_builder *builder)
{
  char *line = poly_off_next_line(text);
  char *cursor = line;
  char *header = line ? poly_next_token(&cursor) : NULL;
  if (!header || !poly_equal_nocase(header, "OFF"))
    return poly_fail(text->message, text->message_size, POLY_ERROR_PARSE,
                          "mesh file '%s' line %d: missing 'OFF' header", text->path, text->line);
  /* The counts may share the header line ("OFF 8 6 0") or follow it. */
  char *rest = cursor;
  while (*rest && poly_is_space(*rest)) rest++;
  if (!*rest) {
    line = poly_off_next_line(text);
    cursor = line ? line : rest;
  }
  /* A third count (edges) may follow; OFF readers conventionally ignore it. */
  long num_vertices, num_faces;
  if (!poly_off_parse_count(&cursor, &num_vertices) || !poly_off_parse_count(&cursor, &num_faces) ||
      num_vertices > INT_MAX / 3)
    return poly_fail(text->message, text->message_size, POLY_ERROR_PARSE,
                          "mesh file '%s' line %d: expected vertex and face counts", text->path,
                          text->line);
  for (long i = 0; i < num_vertices; i++) {
    int out_of_memory = 0;
    line = poly_off_next_line(text);
    cursor = line;
    if (!line)
      return poly_fail(text->message, text->message_size, POLY_ERROR_PARSE,
                            "mesh file '%s' line %d: file ends before vertex %ld of %ld", text->path,
                            text->line, i + 1, num_vertices);
    if (!poly_parse_vertex(&cursor, builder, &out_of_memory))
      return out_of_memory ? poly_text_out_of_memory(text)
                           : poly_fail(text->message, text->message_size, POLY_ERROR_PARSE,
                                            "mesh file '%s' line %d: vertex %ld of %ld needs 3 "
                                            "finite numbers",
                                            text->path, text->line, i + 1, num_vertices);
  }
  int *corners = NULL, corner_capacity = 0;
  poly_status status = POLY_OK;
  for (long f = 0; f < num_faces && status == POLY_OK; f++) {
    long size, index;
    char *stop;
    int count = 0;
    line = poly_off_next_line(text);
    cursor = line;
    if (!line || !poly_off_parse_count(&cursor, &size) || size < 3) {
      status = poly_fail(text->message, text->message_size, POLY_ERROR_PARSE,
                              "mesh file '%s' line %d: %s face %ld of %ld (a vertex count >= 3, "
                              "then the indices)",
                              text->path, text->line, line ? "bad" : "file ends before", f + 1,
                              num_faces);
      break;
    }
    for (long k = 0; k < size && status == POLY_OK; k++) {
      char *token = poly_next_token(&cursor);
      if (!token || !poly_parse_int(token, &index, &stop) || *stop != '\0' || index < 0 ||
          index >= num_vertices)
        status = poly_fail(text->message, text->message_size, POLY_ERROR_PARSE,
                                "mesh file '%s' line %d: face %ld needs %ld vertex indices in "
                                "0..%ld, got '%.40s'",
                                text->path, text->line, f + 1, size, num_vertices - 1,
                                token ? token : "end of line");
      else if (!poly_push_corner(&corners, &count, &corner_capacity, (int)index))
        status = poly_text_out_of_memory(text);
    }
    /* Anything after the indices is a per-face colour. */
    if (status == POLY_OK && !poly_add_fan(builder, corners, count))
      status = poly_text_out_of_memory(text);
  }
  free(corners);
  return status;
}

/* ------------------------------------------------------------------ entry */

static poly_status poly_read_file(const char *path, char **data, size_t *size, char *message,
                                  size_t message_size)
{
  FILE *file = fopen(path, "rb");
  if (!file)
    return poly_fail(message, message_size, POLY_ERROR_FILE, "cannot open mesh file '%s': %s",
                          path, strerror(errno));
  size_t capacity = 1 << 16, length = 0;
  char *buffer = (char *)malloc(capacity);
  while (buffer) {
    length += fread(buffer + length, 1, capacity - 1 - length, file);
    if (length < capacity - 1) break;
    char *grown = capacity <= SIZE_MAX / 2 ? (char *)realloc(buffer, capacity * 2) : NULL;
    if (!grown) free(buffer);
    buffer = grown;
    capacity *= 2;
  }
  int failed = buffer && ferror(file);
  fclose(file);
  if (!buffer)
    return poly_fail(message, message_size, POLY_ERROR_MEMORY,
                          "mesh file '%s': out of memory while reading", path);
  if (failed) {
    free(buffer);
    return poly_fail(message, message_size, POLY_ERROR_FILE, "cannot read mesh file '%s'", path);
  }
  buffer[length] = '\0';
  *data = buffer;
  *size = length;
  return POLY_OK;
}

static const char *poly_extension(const char *path)
{
  const char *slash = strrchr(path, '/');
  const char *backslash = strrchr(path, '\\');
  const char *base = slash ? slash + 1 : path;
  if (backslash && backslash + 1 > base) base = backslash + 1;
  const char *dot = strrchr(base, '.');
  return dot ? dot : "";
}

poly_status poly_mesh_read(const char *path, poly_mesh *mesh, char *message, size_t message_size)
{
  if (message && message_size > 0) message[0] = '\0';
  if (!mesh) return poly_fail(message, message_size, POLY_ERROR_FILE, "no mesh to read into");
  memset(mesh, 0, sizeof *mesh);
  if (!path) return poly_fail(message, message_size, POLY_ERROR_FILE, "no mesh file name given");
  const char *extension = poly_extension(path);
  int is_stl = poly_equal_nocase(extension, ".stl");
  int is_obj = poly_equal_nocase(extension, ".obj");
  int is_off = poly_equal_nocase(extension, ".off");
  if (!is_stl && !is_obj && !is_off)
    return poly_fail(message, message_size, POLY_ERROR_FILE,
                          "mesh file '%s' has unknown extension '%s' (use .stl, .obj or .off)", path,
                          extension);
  char *data = NULL;
  size_t size = 0;
  poly_status status = poly_read_file(path, &data, &size, message, message_size);
  if (status != POLY_OK) return status;
  if (size == 0) {
    free(data);
    return poly_fail(message, message_size, POLY_ERROR_EMPTY,
                          "mesh file '%s' is empty: no triangles", path);
  }
  poly_text text = {data, data + size, 0, path, message, message_size};
  poly_mesh_builder builder;
  memset(&builder, 0, sizeof builder);
  if (is_stl)
    status = poly_read_stl(data, size, &text, &builder);
  else if (is_obj)
    status = poly_read_obj(&text, &builder);
  else
    status = poly_read_off(&text, &builder);
  free(data);
  if (status != POLY_OK) {
    poly_mesh_free(&builder.mesh);
    return status;
  }
  *mesh = builder.mesh;
  return POLY_OK;
}

void poly_mesh_free(poly_mesh *mesh)
{
  if (!mesh) return;
  free(mesh->vertices);
  free(mesh->triangles);
  memset(mesh, 0, sizeof *mesh);
}

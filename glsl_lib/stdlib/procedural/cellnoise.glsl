// requires: stdlib/procedural/hash.glsl
// Cellular (value-per-cell) noise: the lookup3 hash of the integer lattice cell, as in Worley (1996) and OSL's "cellnoise".

float mg_cellnoise(float p)
{
    return mg_hash_to_01(mg_hash(mg_floor_int(p)));
}

float mg_cellnoise(vec2 p)
{
    return mg_hash_to_01(mg_hash(mg_floor_int(p.x), mg_floor_int(p.y)));
}

float mg_cellnoise(vec3 p)
{
    return mg_hash_to_01(mg_hash(mg_floor_int(p.x), mg_floor_int(p.y), mg_floor_int(p.z)));
}

float mg_cellnoise(vec4 p)
{
    return mg_hash_to_01(mg_hash(mg_floor_int(p.x), mg_floor_int(p.y), mg_floor_int(p.z), mg_floor_int(p.w)));
}

// three independent values per cell: the cell hashed with a trailing channel index
vec3 mg_cellnoise_vec3(vec2 p)
{
    int x = mg_floor_int(p.x), y = mg_floor_int(p.y);
    return vec3(mg_hash_to_01(mg_hash(x, y, 0)), mg_hash_to_01(mg_hash(x, y, 1)), mg_hash_to_01(mg_hash(x, y, 2)));
}

vec3 mg_cellnoise_vec3(vec3 p)
{
    int x = mg_floor_int(p.x), y = mg_floor_int(p.y), z = mg_floor_int(p.z);
    return vec3(mg_hash_to_01(mg_hash(x, y, z, 0)), mg_hash_to_01(mg_hash(x, y, z, 1)),
                mg_hash_to_01(mg_hash(x, y, z, 2)));
}

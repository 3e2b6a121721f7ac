// UDIM / UVTILE tiles: each tile's texture covers one unit square of uv (MaterialX Specification 1.39, "Filename Substitutions"); gradients come from the continuous uv so mip selection ignores the tile seams.
vec4 mg_udim_read(sampler2D tile, vec2 uv, ivec2 cell)
{
    return textureGrad(tile, uv - vec2(cell), dFdx(uv), dFdy(uv));
}

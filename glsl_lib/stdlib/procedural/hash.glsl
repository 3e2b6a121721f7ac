// Integer hashing after Bob Jenkins, "lookup3.c" (2006, public domain): hashword() with mix() and final().

uint mg_rotl32(uint x, int k)
{
    return (x << uint(k)) | (x >> uint(32 - k));
}

// lookup3 mix(): reversible mixing of three 32-bit words
void mg_jenkins_mix(inout uint a, inout uint b, inout uint c)
{
    a -= c;  a ^= mg_rotl32(c, 4);   c += b;
    b -= a;  b ^= mg_rotl32(a, 6);   a += c;
    c -= b;  c ^= mg_rotl32(b, 8);   b += a;
    a -= c;  a ^= mg_rotl32(c, 16);  c += b;
    b -= a;  b ^= mg_rotl32(a, 19);  a += c;
    c -= b;  c ^= mg_rotl32(b, 4);   b += a;
}

// lookup3 final(): avalanche of three words into c
void mg_jenkins_final(inout uint a, inout uint b, inout uint c)
{
    c ^= b;  c -= mg_rotl32(b, 14);
    a ^= c;  a -= mg_rotl32(c, 11);
    b ^= a;  b -= mg_rotl32(a, 25);
    c ^= b;  c -= mg_rotl32(b, 16);
    a ^= c;  a -= mg_rotl32(c, 4);
    b ^= a;  b -= mg_rotl32(a, 14);
    c ^= b;  c -= mg_rotl32(b, 24);
}

// hashword() of n words with initval 13: a = b = c = 0xdeadbeef + 4n + 13
uint mg_jenkins_seed(uint n)
{
    return 0xdeadbeefu + (n << 2u) + 13u;
}

uint mg_hash(int x)
{
    uint a = mg_jenkins_seed(1u), b = a, c = a;
    a += uint(x);
    mg_jenkins_final(a, b, c);
    return c;
}

uint mg_hash(int x, int y)
{
    uint a = mg_jenkins_seed(2u), b = a, c = a;
    a += uint(x);
    b += uint(y);
    mg_jenkins_final(a, b, c);
    return c;
}

uint mg_hash(int x, int y, int z)
{
    uint a = mg_jenkins_seed(3u), b = a, c = a;
    a += uint(x);
    b += uint(y);
    c += uint(z);
    mg_jenkins_final(a, b, c);
    return c;
}

uint mg_hash(int x, int y, int z, int w)
{
    uint a = mg_jenkins_seed(4u), b = a, c = a;
    a += uint(x);
    b += uint(y);
    c += uint(z);
    mg_jenkins_mix(a, b, c);
    a += uint(w);
    mg_jenkins_final(a, b, c);
    return c;
}

uint mg_hash(int x, int y, int z, int w, int v)
{
    uint a = mg_jenkins_seed(5u), b = a, c = a;
    a += uint(x);
    b += uint(y);
    c += uint(z);
    mg_jenkins_mix(a, b, c);
    a += uint(w);
    b += uint(v);
    mg_jenkins_final(a, b, c);
    return c;
}

// three 8-bit hashes from the low bytes of one word (one per vector channel)
uvec3 mg_hash_bytes3(uint h)
{
    return uvec3(h, h >> 8u, h >> 16u) & uvec3(0xFFu);
}

// a 32-bit hash mapped onto [0, 1]
float mg_hash_to_01(uint h)
{
    return float(h) / float(0xFFFFFFFFu);
}

// integer lattice cell containing x, and the position inside it
int mg_floor_int(float x)
{
    return int(floor(x));
}

float mg_floorfrac(float x, out int cell)
{
    cell = mg_floor_int(x);
    return x - float(cell);
}

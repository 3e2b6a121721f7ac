// time / frame (MaterialX Specification 1.39, "Application Nodes"): the application drives u_frame.
uniform float u_frame = 0.0;

float mg_frame()
{
    return u_frame;
}

float mg_time(float fps)
{
    return u_frame / fps;
}

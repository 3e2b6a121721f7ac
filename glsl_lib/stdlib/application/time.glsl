// uniforms: u_frame
// time / frame (MaterialX Specification 1.39, "Application Nodes"): the application drives u_frame.

float mg_frame()
{
    return u_frame;
}

float mg_time(float fps)
{
    return u_frame / fps;
}

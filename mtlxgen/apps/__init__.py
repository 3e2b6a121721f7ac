"""The applications on top of the pipeline: the command line (cli), batches and golden images with their reports
(batch, golden, report, cluster), the live viewer (view, viewpanel, docedit, uniformvalues), WebGL pages and three.js
modules (web, three), USD stage info and drawing, and the test and benchmark tools (reference, glslvalidate).
"""

# Cycles' render settings that every comparison with meshtour shares (bench/cycles_frame.py, the
# speed comparison; bench/cycles_gltf.py, materials and image-based light): the CPU, a fixed number
# of samples without adaptive sampling or denoiser, a fixed seed and thread count, the frame size,
# linear 32-bit EXR out, the Standard view transform.


def apply(scene, spp, seed, threads, width, height, transparent):
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = spp
    scene.cycles.use_adaptive_sampling = False
    scene.cycles.use_denoising = False
    scene.cycles.seed = seed
    scene.render.threads_mode = "FIXED"
    scene.render.threads = threads
    scene.render.resolution_x, scene.render.resolution_y = width, height
    scene.render.resolution_percentage = 100
    scene.render.film_transparent = transparent
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    scene.view_settings.view_transform = "Standard"

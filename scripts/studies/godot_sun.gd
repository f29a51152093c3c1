# godot_sun.gd — run by scripts/studies/godot_sun.sh (Godot 3, `godot3 --path P -s
# res://godot_sun.gd`): renders the imported models m0.glb (the original),
# m1.glb, ... under a DirectionalLight "sun" from each direction asked and an
# ambient light, and writes one PNG per model, view and sun:
# out/m<i>_<view>_az<A>_el<E>.png, transparent where nothing is drawn.
# The frame is the original's: the camera looks at the centre of its
# bounding box from distance radius / sin(fov / 2) (radius: half the box's
# diagonal), as scripts/studies/threejs_sun.mjs frames it. Azimuth 0 is on +Z, 90 on
# +X; the sun shines from (cos EL sin AZ, sin EL, cos EL cos AZ) towards the
# model. Arguments after "--": SIZE FOV AMBIENT MODELS SUNS VIEWS, SUNS as
# AZ:EL,... or "headlight", VIEWS as front,side.
extends SceneTree

var size = 256
var fov = 30.0
var ambient = 0.4
var models = 2
var suns = []
var views = []

func dir_of(az, el):
	var a = deg2rad(az)
	var e = deg2rad(el)
	return Vector3(cos(e) * sin(a), sin(e), cos(e) * cos(a))

func aabb_of(node, xf):
	var box = null
	var t = xf * node.transform if node is Spatial else xf
	if node is MeshInstance and node.mesh:
		box = t.xform(node.get_aabb())
	for c in node.get_children():
		var b = aabb_of(c, t)
		if b != null:
			box = b if box == null else box.merge(b)
	return box

func _init():
	var args = Array(OS.get_cmdline_args())
	var i = args.find("--")
	var a = []
	if i >= 0:
		for k in range(i + 1, args.size()):
			a.append(args[k])
	else:
		# Godot 3 passes the arguments after the script's path.
		for s in args:
			if not s.begins_with("-") and not s.ends_with(".gd"):
				a.append(s)
	size = int(a[0])
	fov = float(a[1])
	ambient = float(a[2])
	models = int(a[3])
	if a[4] == "headlight":
		suns = ["headlight"]
	else:
		for s in a[4].split(","):
			var p = s.split(":")
			suns.append(Vector2(float(p[0]), float(p[1])))
	views = a[5].split(",")
	call_deferred("run")

func run():
	# A viewport of its own, transparent where nothing is drawn (the window's
	# keeps no alpha), rendering every frame.
	var win = get_root()
	OS.window_size = Vector2(size, size)
	var root = Viewport.new()
	root.size = Vector2(size, size)
	root.transparent_bg = true
	root.hdr = false
	root.own_world = true
	root.render_target_update_mode = Viewport.UPDATE_ALWAYS
	root.render_target_v_flip = false
	win.add_child(root)
	var env = Environment.new()
	env.background_mode = Environment.BG_CLEAR_COLOR
	env.ambient_light_color = Color(1, 1, 1)
	env.ambient_light_energy = ambient
	env.ambient_light_sky_contribution = 0.0
	env.tonemap_mode = Environment.TONE_MAPPER_LINEAR
	var we = WorldEnvironment.new()
	we.environment = env
	root.add_child(we)
	var sun = DirectionalLight.new()
	sun.light_energy = 1.0
	sun.shadow_enabled = false
	root.add_child(sun)
	var cam = Camera.new()
	cam.fov = fov
	cam.keep_aspect = Camera.KEEP_HEIGHT
	cam.current = true
	root.add_child(cam)
	var center = Vector3()
	var radius = 1.0
	for m in range(models):
		var scene = load("res://m%d.glb" % m)
		if scene == null:
			printerr("godot_sun.gd: cannot load m%d.glb" % m)
			quit(4)
			return
		var inst = scene.instance()
		root.add_child(inst)
		if m == 0:
			var box = aabb_of(inst, Transform())
			center = box.position + box.size * 0.5
			radius = box.size.length() * 0.5
		var d = radius / sin(deg2rad(fov) / 2.0)
		cam.near = max(d - 1.5 * radius, 0.01 * d)
		cam.far = d + 1.5 * radius
		for v in views:
			var vaz = 0.0 if v == "front" else 90.0
			var eye = center + dir_of(vaz, 10.0) * d
			cam.look_at_from_position(eye, center, Vector3.UP)
			for s in suns:
				var name = ""
				if typeof(s) == TYPE_STRING:
					sun.look_at_from_position(eye, center, Vector3.UP)
					name = "m%d_%s_head_light.png" % [m, v]
				else:
					var from = center + dir_of(s.x, s.y) * d
					sun.look_at_from_position(from, center, Vector3.UP if abs(s.y) < 89.0 else Vector3.FORWARD)
					name = "m%d_%s_az%d_el%d.png" % [m, v, int(s.x), int(s.y)]
				# two frames: the first after a change may show the old state
				yield(self, "idle_frame")
				yield(self, "idle_frame")
				yield(VisualServer, "frame_post_draw")
				var img = root.get_texture().get_data()
				img.flip_y()
				img.save_png("res://out/" + name)
		root.remove_child(inst)
		inst.queue_free()
	quit(0)

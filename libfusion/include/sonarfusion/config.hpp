// Every parameter of the pipeline, with the paper's default and a one-line why.
// Angles are stored in radians; the defaults are written in degrees for reading.
#pragma once

#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace sonarfusion {

constexpr double kDegToRad = M_PI / 180.0;
// Hard limits on sizes a config or a message may claim (one definition, used by
// the validators and the daemon's message guard).
constexpr int kMaxFlsBeams = 4096, kMaxFlsRows = 16384, kMaxPsBins = 65536, kMaxMapCells = 4096;
constexpr int kMaxNavTimelineConfirm = 64;
constexpr int kMaxSurveyMaps = 64;
constexpr int kMaxFlsGeometries = 64;

// A value a config struct cannot take: its key as the YAML files spell it,
// relative to the struct's own block ("nx" in map:, "range_max" in fls:;
// MapperConfig::validate() gives the whole key, "map.nx"), and why. Each
// struct's validate() returns none when every value is fine. No I/O: the
// loaders add the file's name (docs/mapper-config.md).
struct ConfigIssue {
    std::string key;
    std::string reason;  // e.g. "must be in 1..4096"
    [[nodiscard]] std::string message() const { return key + ": " + reason; }
    // The same issue one block further out: in("map") turns "nx" into "map.nx".
    [[nodiscard]] ConfigIssue in(const std::string& block) const {
        return {key.empty() ? block : block + "." + key, reason};
    }
};

// Forward-looking sonar (DIDSON, paper Table 1).
struct FlsGeometry {
    double fov_horizontal = 29.0 * kDegToRad;  // theta_F
    double elevation_min = -7.0 * kDegToRad;   // phi_min
    double elevation_max = 7.0 * kDegToRad;    // phi_max
    double tilt = 40.0 * kDegToRad;            // phi_t1, positive looks down
    double range_min = 0.83;                   // m
    double range_max = 10.0;                   // m
    int beams = 96;                            // w
    int rows = 512;                            // h (range bins)
    int elevation_samples = 5;                 // N_v
    // Optional non-uniform geometry (as carried in fls_image_t). When empty the
    // uniform paper geometry of Eqs. 1-2 is used.
    std::vector<double> beam_bearing;  // rad per column, size == beams
    std::vector<double> row_range;     // m per row (row 0 far), size == rows
    [[nodiscard]] std::optional<ConfigIssue> validate() const;  // keys of the `fls` block
};

// Profiling sonar (Imagenex 881A, paper Table 2).
struct PsGeometry {
    double fan_min = -10.0 * kDegToRad;  // theta_min
    double fan_max = 10.0 * kDegToRad;   // theta_max
    double head_min = -20.0 * kDegToRad; // phi_p sector limits
    double head_max = 20.0 * kDegToRad;
    double tilt = 40.0 * kDegToRad;      // phi_t2
    double range_min = 0.0;              // m, range of bin 0
    double range_max = 10.0;             // m, range of the last bin
    int bins = 500;                      // range bins per ping (2 cm)
    int fan_samples = 21;                // N_h
    // The fan's thickness (its thin, vertical direction; the 881A-like sensor
    // the simulator models: 2 deg). A return may come from anywhere across it;
    // the detector places a ping's nearest echo on the fan's steepest edge,
    // where a level seabed returns first (DetectorConfig::nearest_echo_sigmas).
    double beam_width_vertical = 2.0 * kDegToRad;
    [[nodiscard]] std::optional<ConfigIssue> validate() const;  // keys of the `ps` block
};

// Where a sensor sits on the vehicle (body frame FRD). The paper mounts both at
// the vehicle origin; the tilt is part of the sensor model (Eqs. 4, 11).
struct Mounting {
    double x = 0.0, y = 0.0, z = 0.0;  // m
    double roll = 0.0, yaw = 0.0;      // rad, extra rotation besides the tilt
    [[nodiscard]] std::optional<ConfigIssue> validate() const;  // keys of the `mount` block
};

struct MapConfig {
    int nx = 100, ny = 100, nz = 100;  // 10 x 10 x 10 m at 0.1 m (paper 2.1)
    double resolution = 0.1;           // m
    float clamp_min = -5.0f;           // Eq. 8
    float clamp_max = 5.0f;
    // Place the map's min corner on the world lattice (multiples of resolution)
    // instead of exactly at detection point - extent/2, so that the voxels do not
    // depend on which echoes declared the object (issue 9: a 4 cm shift of the
    // anchor moved a 0.6 m mine's visible recall between 0.76 and 1.0).
    bool snap_to_world_lattice = true;
    [[nodiscard]] std::optional<ConfigIssue> validate() const;  // keys of the `map` block
};

// Which of the paper's stages run and how evidence is counted. The four
// variants of docs/design.md ("Variants") are presets of this struct (see variant.hpp).
struct UpdateConfig {
    bool fls_enabled = true;
    bool ps_carving_enabled = true;
    // Eq. 5: P_o; the paper leaves it open. 0.7 is a moderate hit.
    double p_occupied = 0.7;
    // Eq. 6: alpha_F, the FLS weight relative to the PS.
    double alpha_fls = 0.3;
    // Eq. 12: P_f < 0.5. 0.2 carves strongly enough to keep up with the FLS.
    double p_free = 0.2;
    // Eq. 13: alpha_P, how fast carving fades along the ray.
    double alpha_ps = 0.5;
    // FLS pixel threshold (paper 2.2: 150 of 255).
    int fls_intensity_threshold = 150;
    // Count each voxel at most once per FLS frame with the strongest intensity
    // that fell in it (docs/design.md, "FLS log-odds update": evidence counting;
    // OctoMap does the same).
    bool fls_once_per_frame = true;
    // Spacing of the candidate points along each elevation arc, in voxels. A
    // fixed N_v = 5 over 14 deg puts them 0.3-0.6 m apart at 5-10 m range, so
    // the arc is dotted across 10 cm voxels; with a spacing > 0 each row gets
    // max(N_v, ceil(r * aperture / (spacing * voxel)) + 1) samples. 0: N_v
    // samples at every range (the paper).
    double fls_arc_spacing_voxels = 1.0;
    // The FLS's own free-space evidence (space carving, Aykin and
    // Negahdaripour): a beam whose first return above the threshold lies at
    // range r saw water along its whole elevation arc before r. Those voxels
    // are freed once per frame (a voxel the same frame also hit is left
    // alone). The paper ignores it.
    bool fls_free_space = true;
    // Where the FLS's free space stops: at the first pixel of a beam that
    // could be an echo, not only at the first one strong enough to vote (>
    // fls_intensity_threshold). A pixel could be an echo when it and the next
    // farther one stand this many robust standard deviations above the
    // image's median (its noise). A surface that returns weakly (grazing, or
    // facing away) is not water. 4 as for the PS (never stopped early by noise
    // over the object-free seabeds). 0: the free space runs up to the first vote.
    double fls_free_space_noise_sigmas = 4.0;
    // How much one frame that saw a voxel as water outweighs one frame that
    // voted it at full intensity: the free update is -ratio * alpha_F *
    // ln(P_o / (1 - P_o)). 3 is the smallest ratio of the two outcomes'
    // log-likelihoods measured against ground truth (sf-fls-evidence +
    // tools/bench/fls_likelihood.py; docs/algorithm.md, "FLS free-space weight").
    double fls_free_vote_ratio = 3.0;
    // A vote also counts as one the seabed cannot explain (VoxelMap::
    // flsAboveSeabedVotes) when its pixel is a highlight (fls_highlight.hpp):
    // bright where the seabed's returns at that range are speckle, in a window
    // of (2 h + 1)^2 pixels, h = fls_highlight_half_window, holding more bright
    // pixels than speckle gives with probability fls_highlight_false_alarm. A
    // low part of an object beside the PS swath returns from no nearer than the
    // seabed does, but brighter (docs/algorithm.md, "Highlights the seabed
    // cannot explain"). False: range alone decides.
    bool fls_highlight_above_seabed = true;
    int fls_highlight_half_window = 2;
    double fls_highlight_false_alarm = 1e-6;
    // The seabed plane those votes are judged against is fitted where the FLS
    // boresight meets the seabed (its footprint), from the PS seabed echoes'
    // lower envelope (ObjectDetector::seabedAlongRay). False: the detector's
    // plane around the newest PS echo, trimmed as for rises. The PS head sweeps
    // its look 3-9 m ahead, so at the far end of each sweep no fit existed
    // there (a fifth of the frames voted nothing above the seabed); and object
    // echoes the detector took as seabed before it had a plane lifted that
    // plane and its scatter until no vote counted (docs/algorithm.md, "The
    // seabed the FLS judges against").
    bool fls_seabed_at_footprint = true;
    // With fls_seabed_at_footprint: an FLS frame judged while no plane existed
    // at its footprint (the mission's first metres, before the detector has
    // min_seabed_echoes there; longer at a sparse ping rate) counted no vote
    // above the seabed. Held (DetectorConfig::replay_fls_frames), its votes are
    // judged again against the first plane found there later, once: the seabed
    // has not moved. Above-seabed counts only, so the log-odds are unchanged
    // (docs/algorithm.md, "Frames seen before the seabed was known").
    bool fls_seabed_judged_later = true;
    // Report as objects only voxels that a PS ray crossed or ended in.
    bool require_ps_observation = true;
    // PS carving stops at the first bin that could be an echo, not at the
    // selected one: the nearer of the nearest group's first bin and the first
    // of two consecutive bins standing this many robust standard deviations
    // (1.4826 x MAD) above the ping's median (its noise). A surface in part of
    // the fan returns weakly, often below the group threshold, and is not
    // water; a ray carried on to the selected echo carves it. The echo itself
    // stays where it was selected. 4 is the smallest multiple at which noise
    // alone never stopped a ping early over the suite's object-free seabeds
    // (docs/algorithm.md, "Carving stops at the first echo"). 0: carve up to
    // the selected echo (the paper, Eq. 13).
    double ps_carve_noise_sigmas = 4.0;
    // And at the first run of bins one voxel (this many voxels) of range long
    // whose mean stands ps_carve_noise_sigmas / sqrt(bins in the run) robust
    // sigmas above the median: a surface struck by only a few of the fan's
    // rays (an object at the fan's edge) returns in every bin of its range
    // below the per-bin level, while the seabed, struck by all of them, forms
    // the nearest group; carried on to that group, the edge rays carve through
    // the object (docs/algorithm.md, "Weak echoes at the fan's edge"). 0: the
    // per-bin pair only. Unused when ps_carve_noise_sigmas is 0.
    double ps_carve_echo_window_voxels = 1.0;
    // A PS ray does not carve a voxel in which PS echoes ended for at least
    // this share of the PS rays that reached it so far (ended in it or crossed
    // it), and for at least ps_carve_spare_min_echoes rays. Echoes say a
    // surface is in the voxel; a ray that crossed it without an echo says part
    // of it is water, or that the surface there faces away: a surface seen
    // from one side returns nothing at grazing incidence from the other, and
    // the rays that then pass through its voxel on their way to a farther echo
    // carved it away (the wedge's ramp, the dog-leg pyramid's faces). 0.3 is
    // the echo share that separated true surface voxels from false ones
    // (docs/algorithm.md, "Carving spares the voxels the PS saw as surface").
    // 0: every voxel a ray crossed is carved (the paper, Eq. 13).
    double ps_carve_spare_echo_share = 0.3;
    // Two rays: one echo alone may be a fan-edge ray of a single ping.
    int ps_carve_spare_min_echoes = 2;
    // PS-only reconstruction: the end voxel of each PS ray gets an occupied
    // update (delta L_o) instead of being left alone. Only the carve_only variant.
    bool ps_endpoint_hits = true;
    [[nodiscard]] std::optional<ConfigIssue> validate() const;  // keys of the `update` block
};

// Closest-group range selection of the PS (paper 2.3).
struct PsSelectionConfig {
    double group_threshold = 0.7;  // tau, on intensities normalised to 0..1
    // Normalise by the ping's own maximum (true) or by 255 (false). Per-ping
    // maximum keeps the rule independent of the sonar's gain setting.
    bool normalise_by_ping_max = true;
    // A ping whose strongest bin is below this (0..255) has no echo: no update.
    int min_peak_intensity = 40;
    // Bins closer than this are ignored (transducer ringing).
    double min_range = 0.3;  // m
    // A bin of at least min_peak_intensity belongs to a group even below
    // tau x the ping's peak: an object in part of the fan returns less than
    // the seabed summed across all of it, and is still the nearest surface.
    // False: tau alone (the paper).
    bool weak_echoes_group = true;
    [[nodiscard]] std::optional<ConfigIssue> validate() const;  // keys of the `ps_selection` block
};

// PS rising-edge object detector that anchors the map (paper 2.1). The seabed
// is a plane fitted to recent seabed echoes near the newest one (so a slope is
// not a rise); an echo is "risen" when it stands above that plane by more than
// the seabed's own scatter allows; an object is declared where risen echoes
// cluster. Nothing here counts pings, so ping rate and head speed do not matter.
struct DetectorConfig {
    double seabed_radius = 3.0;      // m: seabed echoes within this horizontal distance are fitted
    int seabed_capacity = 1024;      // seabed echoes kept (ring, allocated once)
    // Echoes within seabed_radius needed before a rise is judged: more than one
    // head sweep (44 pings), so a first sweep that is mostly object is outvoted.
    int min_seabed_echoes = 60;
    double min_rise = 0.1;           // m: the smallest rise that counts, whatever the scatter
    double rise_sigmas = 4.0;        // a rise must also exceed this many rms seabed residuals
    double cluster_radius = 0.5;     // m: risen echoes this close (horizontally) form one cluster
    int min_risen_echoes = 5;        // risen echoes in one cluster that declare an object
    int risen_capacity = 64;         // risen echoes kept (ring, allocated once)
    // The plane rises are judged against starts from the echoes' lower envelope
    // (ObjectDetector's Trim::LowerEnvelope), then trims as before: object
    // echoes taken as seabed before any plane existed (a PS whose first sweeps
    // fall on the object) do not lift it. False: from all the echoes (paper).
    bool rise_from_lower_envelope = true;
    // The rise trim's last window (the echoes within 3 scatters of the plane,
    // either side) repeats until it keeps the same echoes (at most 16 more
    // times). The cuts before it keep echoes by their depth, which flattens
    // the plane's slope and narrows its scatter on a rough seabed sloping
    // along the track. False: one window, as before.
    bool rise_trim_converges = true;
    // A PS echo is placed on its beam's centre, but a 2 deg thick fan returns
    // from anywhere across its thickness: at range r and depression theta the
    // same echo may lie up to r cos(theta) sin(beam_width_vertical / 2) deeper
    // (0.12 m at 8 m and 33 deg; speckle moves a level seabed's peak across
    // that). With this on, an echo rises only when, placed on its beam's
    // steepest edge (the deepest it can lie), it still stands min_rise above
    // the plane, as well as riseThreshold on its centre. False: the centre
    // alone. Found on object-free seabed at 4.5-5 m altitude, where the far
    // looks declared false objects (docs/algorithm.md, "Echoes from anywhere
    // in the fan's thickness").
    bool rise_from_deepest_in_beam = true;
    // The PS places its echoes on the track line, so a line flown beside an
    // earlier one lies across from all of that line's echoes. With this on, a
    // seabed plane judges only where some of its echoes lie within
    // cluster_radius across their long axis (elsewhere there is no plane yet,
    // and echoes wait as before any plane existed), and the lower envelope's
    // first cut is level along that axis and tilted across it as the echoes
    // lie. False: the level cut over every echo within seabed_radius, and a
    // plane wherever min_seabed_echoes lie: on a 5 deg slope across two
    // passes 2 m apart the uphill line stood 0.17 m above the downhill line's
    // plane (docs/algorithm.md, "Two lines on a slope across them").
    bool seabed_across_lines = true;
    // With seabed_across_lines, where the disc holds echoes of other lines
    // (more than cluster_radius across from xy), the lower envelope's second
    // halving cuts each group (the echoes on xy's own line, the others) at
    // that group's own median residual about the plane the first cut gives,
    // over the group's echoes the first cut kept. One cut over the disc let a
    // dense old line decide the new line's: on a 5 deg slope across
    // two lines, 5 mm per ping, the second cut kept 2 of the new line's 9
    // echoes, the plane's tilt across decayed to level and the uphill line's
    // seabed rose 0.18 m above it (docs/algorithm.md, "A new line beside a
    // dense old one"). False: one cut over the whole disc.
    bool envelope_per_line = true;
    // Echoes taken before a plane existed where they lie are judged when one
    // first does there: a risen one joins the risen echoes (and leaves the
    // seabed's fits). False: they stay seabed for good.
    bool judge_early_echoes = true;
    // Each such echo is also judged by the plane fitted where it lies, and
    // the one of the two planes with the smaller scatter decides: the early
    // echoes are in both fits, and an object's among them lift a plane and
    // widen its scatter (a low mine 0.5 m off in the first sweeps: a first
    // plane of 0.09 m scatter, a rise threshold of 0.36 m over a 0.3 m mine;
    // docs/algorithm.md, "Early echoes judged by the tighter plane"). False:
    // the plane at the newest echo judges them all.
    bool judge_early_echoes_by_tighter_plane = true;
    // PS pings kept (ring, allocated once, 168 B each) and carved into a map
    // when the detector anchors it: the pings that looked at its stretch before
    // it existed. 0: a map starts with the ping after the detection (paper).
    int replay_pings = 1024;
    // The held pings carve only: their free-space updates, as log-odds alone
    // (no echo, crossing or PS-observed flag; those count the pings the map was
    // made from). Their echoes, far looks placed across the whole fan, add
    // echoes above the seabed beside an object (docs/algorithm.md, "The pings
    // before the map carve it"). False: carved with their echoes, as if the map
    // had existed ("A mission that starts close to an object").
    bool replay_pings_carve_only = true;
    // With replay_pings_carve_only: when the map was declared by echoes taken
    // before any seabed plane stood where they lie (judge_early_echoes) and the
    // PS sector's near edge has come within cluster_radius of the detection
    // (Mapper::psSectorHasPassed), the held pings whose echo rises above the
    // detector's seabed (ObjectDetector::heldEchoRises) are replayed whole,
    // echo, crossings and flags, as live pings. Then those looks are all the
    // PS will give of the object on this pass: a pass starting 5 m before a
    // mine at 4 m altitude holds it from its first pings, and with carving
    // only the map held no PS echo of it and no object. Where the PS still
    // looks at the object after the detection, its far looks would only smear
    // echoes across the fan, and every held ping carves only, as before
    // (docs/algorithm.md, "The held pings that saw the object"). False: every
    // held ping carves only.
    bool replay_risen_pings_whole = true;
    // FLS frames kept (ring, allocated once: copies of the configured
    // geometry's images, 128 x 49 KB for 512 x 96, with their poses and the
    // seabed their votes were judged against) and applied to a map when the
    // detector anchors it, in their order, where they reach it (as if the map
    // had existed): the FLS sees an object from range_max (10 m), the PS
    // declares it 3-6 m ahead, and a low object beside the PS fan leaves the
    // FLS fan within a metre of its shadows declaring it. 128 frames are 5 m
    // of travel at the suite's 4 cm per frame. Frames of another geometry are
    // not kept. 0: a map starts with the frame after the detection (paper)
    // (docs/algorithm.md, "The looks before the detection").
    int replay_fls_frames = 128;
    // A ping's nearest echo rises too: in the PS's tilted fan every bearing
    // meets a level seabed at the same range, so a return nearer than the
    // seabed's comes from above it, however weak. Paper 2.1 takes only the
    // strongest bin, which a narrow object loses to the seabed echoing across
    // the whole fan (a barrier 0.5 m off the track at 5 m altitude: 1 ping of
    // 1300). When the strongest echo does not rise (or the ping has none), the
    // nearest bin that could be an echo (firstEchoBin: it and the next stand
    // this many robust sigmas above the ping's median) is judged against the
    // same plane, and counts as the ping's risen echo if it rises; it never
    // enters the seabed's fits. 0: the strongest bin only (paper)
    // (docs/algorithm.md, "Narrow objects lose the strongest bin to the seabed").
    double nearest_echo_sigmas = 4.0;
    // FLS frames are evidence too: a frame holding pixels above the vote
    // threshold from nearer than the seabed could return anywhere on their
    // beams' elevation arcs (the detector's plane where the boresight meets
    // the seabed, raised by 3 rms of its scatter and half a voxel, as for the
    // votes the seabed cannot explain) saw something standing above it; the
    // mean of those pixels, each on its arc's centre line, is one risen echo
    // (one per frame). The PS fan is +-10 deg, the FLS's +-14.5: an object 1 m
    // beside a track flown at 4.5 m returns to no PS ping from above the
    // seabed and to a third of the FLS frames (docs/algorithm.md, "Objects
    // beside the PS fan: the FLS detects"). Off by default: maps it anchors
    // earlier take in the far looks of the first pass, which cost two probe
    // scenarios more than it gained (the same section). False: the PS alone
    // detects (paper).
    bool fls_nearer_than_seabed = false;
    // FLS frames hold shadows too: an object on the seabed hides the seabed
    // behind it, and those pixels go dark for a run of rows that speckle
    // seldom makes. A frame's rarest dark run inside the seabed band (the same
    // plane and margin as above), starting after a seabed return, is a shadow
    // when the frame's own dark statistics (a two-state chain fitted to its
    // band pixels, per part of the band) expect fewer such runs than this per
    // frame (flsShadowOnSeabed); it is placed where it starts on the seabed,
    // just behind the object. A low object beside the track at low altitude
    // leaves the FLS fan before it returns from nearer than the seabed, and
    // no PS ping holds it: its shadow is the evidence there is
    // (docs/algorithm.md, "Shadows: the FLS detects what lies beside the PS fan").
    // 0: no shadow evidence.
    double fls_shadow_false_alarm = 1e-5;
    // Shadows from this many FLS frames within cluster_radius of each other
    // declare an object: one frame's shadow may be a glitch of that frame (a
    // fish, a dropout); at fls_shadow_false_alarm per frame, two speckle
    // shadows falling on the same 0.5 m of seabed are far rarer still.
    int fls_shadow_min_frames = 2;
    // A shadow returns nothing: a dark run is one only when its mean pixel is
    // nearer the mean of the water column's dark pixels (the receiver's noise
    // alone) than that of the seabed band's dark pixels. A seabed turned away
    // from the sonar (a swell's lee, a slope falling away) returns weakly, at
    // or under the noise level for a long run of rows, and those runs are
    // brighter than noise (docs/algorithm.md, "A seabed turned away is no
    // shadow"). False: darkness alone.
    bool fls_shadow_like_water = true;
    [[nodiscard]] std::optional<ConfigIssue> validate() const;  // keys of the `detector` block
};

// Map completion and object segmentation (paper 2.4).
struct SegmentationConfig {
    double occupied_probability = 0.7;  // threshold on Eq. 9
    double baseline_window = 3.0;       // m, moving-average window of the seabed
    // The seabed height field: per column, the mean height of the PS echoes
    // that ended there (the PS measures height to a few cm; the FLS does not),
    // then a local plane fitted over a square window (so a sloping seabed is
    // followed, and no trajectory shape is assumed). Columns no PS echo reached
    // take the plane of their neighbourhood. False: the top of the lowest run
    // of occupied voxels, averaged as below.
    bool seabed_from_ps_echoes = true;
    // With seabed_from_ps_echoes false: average along the track (paper 2.4)
    // when the along-track axis is known (Segmenter::setAlongTrack); otherwise,
    // or when false, a square window.
    bool baseline_along_track = true;
    double min_object_height = 0.15;    // m above the baseline
    int min_object_voxels = 10;         // smaller connected groups are noise
    // Voxels above the baseline but below min_object_height join an object only
    // from a voxel in the layer above them (hysteresis downward only). When
    // false they join from any side, and the seabed surface voxels, which lie in
    // that band too, carry an object out along the whole seabed.
    bool low_layers_from_above = true;
    // With low_layers_from_above, a low voxel joins diagonally down (the
    // object's foot widening in the low band) only where the map shows the
    // object widening there: the voxel holds fls_above_seabed_min_votes (at
    // least 1) FLS votes the seabed cannot explain, or the face recedes at the
    // voxel it joins from (nothing occupied on that voxel, the voxel one step
    // back over it occupied). Beside a vertical wall the low band is the
    // seabed, PS-confirmed and at the seabed's height for the FLS; it joined
    // as a ring one voxel wide (docs/algorithm.md, "The ring beside vertical
    // walls"). false: from any of the nine voxels of the layer above.
    bool low_layers_widen_where_seen = true;
    int max_objects = 64;               // fixed-size result
    // The flood fill's join rules are one-way (a low voxel joins only from
    // above, a seabed voxel only straight down, ...), so which voxels an
    // object takes depends on where its flood started: a ring flooded from its
    // two highest points came out as two objects side by side. With this on,
    // a flood that touches a voxel an earlier flood took (by the rule that
    // voxel joins by, or anywhere above the seabed's own voxel) joins that
    // object when it was kept, and takes the voxel over when its group was
    // dropped as too small (docs/algorithm.md, "One object, one flood").
    // False: each flood keeps only what it reached first.
    bool join_touching_floods = true;
    // Voxels no PS ray ever crossed or ended in (outside the PS swath, inside
    // the wider FLS fan) may extend a PS-confirmed object by up to this many
    // voxels (26-connected steps), on FLS evidence alone; they never seed one.
    int fls_only_extension = 0;
    // Voxels no PS ray ever crossed or ended in join a PS-confirmed object
    // (from any side, any number of steps; they never seed one) when at least
    // this many FLS frames voted them with a return the seabed cannot explain
    // (VoxelMap::flsAboveSeabedVotes). 0: off. The YAML loader derives it when
    // absent: the fewest full-intensity votes that alone reach
    // occupied_probability, ceil(logit(occupied_probability) /
    // (alpha_fls logit(p_occupied))); 4 with the defaults.
    int fls_above_seabed_min_votes = 4;
    // Such a voxel joins only when the voxel under it is not water a sensor saw
    // (log-odds below 0): the FLS knows no elevation, and a vote standing over
    // observed water is an elevation alias (the reference 60 deg box's last false
    // voxels, 1.5 voxels beside its side walls' top edges). An object on the
    // seabed stands on something. False: the votes alone decide.
    bool fls_only_needs_support = true;
    // Such a voxel (and an fls_only_extension one) joins an object only up to
    // one layer above the object's highest PS-confirmed voxel: the PS measured
    // how high the object stands wherever it saw it, while the FLS's elevation
    // aliases of a surface flown along lie on arcs rising above it, return at
    // the same range as the surface and so count as votes the seabed cannot
    // explain (docs/algorithm.md, "FLS-only voxels above what the PS saw").
    // The one layer: the top surface may reach into the voxel above the
    // highest confirmed one. False: no height limit.
    bool fls_only_not_above_ps_top = true;
    // A voxel in the low band (above the seabed by less than
    // min_object_height) that holds PS echoes of its own, too few for the
    // confirmation threshold, joins an object from any side (never seeds one)
    // when the FLS voted it with at least fls_above_seabed_min_votes returns the
    // seabed cannot explain, as an off-swath voxel does: the PS saw a surface at
    // that height, the FLS saw something stand above the seabed on that bearing.
    // A low part at the PS swath's edge (a frame's runners, 0.175 m) holds a few
    // echoes against a threshold its neighbours' set, and joins only from above
    // otherwise (docs/algorithm.md, "Low parts both sensors saw"). False: it
    // joins only from the layer above.
    bool low_echoes_seen_above_seabed = true;
    // A voxel PS rays crossed, with no PS echo of its own, joins an object as
    // an off-swath voxel does (from any side, never seeding one; with
    // fls_above_seabed_min_votes above-seabed votes, standing on something)
    // when those votes exceed this many per PS ray that crossed it
    // (VoxelMap::psCrossings), only up to the object's highest PS-confirmed
    // layer and only from its own layer or the one above (never climbing: a
    // surface above would have stopped the rays). The log-odds clamp (Eq. 8) hides how many updates of
    // each kind a voxel took; this compares them unclamped: a full-intensity
    // FLS vote adds alpha_fls logit(p_occupied) (Eq. 6), a crossing at the far
    // end of its ray, where Eq. 13 carves least, logit(p_free) exp(-alpha_ps).
    // The YAML loader derives it so when absent (3.31 with the defaults). A
    // narrow object at the PS fan's edge returns too weakly to stop the rays
    // that cross it, while the FLS sees it stand above the seabed
    // (docs/algorithm.md, "Crossed by the PS, seen by the FLS"). 0: off.
    double fls_votes_per_ps_crossing = 3.31;
    // The foot of a sloped face reaches one voxel further out in the voxel the
    // seabed runs through: that voxel joins an object one step across from the
    // object's voxel in the layer above it when the map shows a face receding
    // from there one voxel per layer over the three layers above (a staircase
    // of occupied voxels, each with nothing on it but the top one; a diagonal
    // step needs it along x and y as well), so the face slopes on down and out
    // through the seabed voxel. A vertical wall has itself above its lowest
    // voxel; a rounded body's undercut foot and a low bar's end make no such
    // staircase: they keep joining only straight down. The seabed voxels an
    // object holds do not count toward min_object_voxels (docs/algorithm.md,
    // "The foot of a sloped face"). False: the seabed voxel joins only
    // straight down and counts.
    bool base_follows_sloped_faces = true;
    // Occupied voxels the PS did not confirm join an object when they lie
    // straight below one of its voxels (down to the seabed baseline): the PS
    // looks down at 20-60 deg and never sees under an object's top edge or the
    // lower flanks of a rounded body, while the FLS does.
    bool fill_below_objects = true;
    // With fill_below_objects: an occupied voxel PS rays crossed on their way to
    // an echo farther out joins straight down only when the FLS voted it at least
    // once from nearer than the seabed (fls above-seabed votes). Below an
    // object's top the PS is shadowed: no ray crosses there. A ray that did
    // cross went on past the voxel, and with no FLS vote the seabed cannot
    // explain, every vote it holds is the seabed's own return on its elevation
    // arc: water under an overhang (a pipe with one end raised), not the body
    // (docs/algorithm.md, "The fill below stops at water the PS crossed").
    // Maps without crossing counts (SFMAP001/002) keep the fill. False: every
    // occupied voxel straight below joins.
    bool fill_below_not_through_crossed_water = true;
    // With fill_below_objects: the fill also passes through voxels no update
    // ever reached (log-odds at the prior, no flag), down to the voxel the seabed
    // runs through. The sonars look down: space under an object's surface that
    // neither saw lies in the object's shadow, and an object resting on the
    // seabed fills it (a horizontal cylinder's lower flank under its bulge).
    // Open space under an overhang is seen from the side, so it is not unobserved.
    bool fill_below_through_unobserved = true;
    // With fill_below_through_unobserved: under a voxel of the object that no
    // update reached either, the fill may also step one voxel sideways per layer
    // down (the lattice's diagonal), through voxels no update reached, in
    // columns some PS ray reached (elsewhere unobserved means outside the
    // swath, not hidden by the object), in maps the FLS updated too (without
    // its free space the water beside an object is unobserved as well:
    // carve_only), and never beside an occupied voxel (a surface a sensor saw
    // bounds the object there). A face sloping away from
    // every pose (past a pyramid's apex; a cone's far flank flown once off the
    // track) lies beyond each PS ping's first echo and returns to the FLS at
    // the noise level: nothing carved it, and straight down from the part the
    // sensors saw does not reach it (docs/algorithm.md, "The fill below widens
    // through what no sensor observed"). False: straight down only.
    bool fill_below_widens_through_unobserved = true;
    // With seabed_from_ps_echoes: the seabed fit starts from the lower
    // envelope of the echo height field (a morphological opening over
    // baseline_window) instead of a plane through every column, so an object
    // that fills most of the window (a single pass, its shadow unechoed) is
    // left out from the first pass instead of tilting the plane onto its top.
    bool seabed_from_lower_envelope = true;
    // With seabed_from_ps_echoes: a column's seabed height is the echo-weighted
    // mean of its echo voxels' centres (where the echoes were, to within a
    // voxel), not of their top faces (half a voxel shallower).
    bool seabed_at_echo_centres = true;
    // With seabed_from_ps_echoes: before each refit, a column counts as raised
    // (left out of the seabed fit) when its echo height stands above the
    // previous fit by more than this many robust standard deviations (1.4826 x
    // MAD) of all columns' residuals, at least half a voxel (the height field's
    // step) and at most min_object_height. Columns whose echoes mix an object's
    // top with the seabed stand a few cm up; beside low objects (the frame's
    // 0.175 m runners) they lifted the plane by 0.1 m and the objects' lower
    // layers fell below it (docs/algorithm.md, "The seabed fit leaves out what
    // stands out of its own scatter"). 0: min_object_height only.
    double seabed_raised_sigmas = 3.0;
    // PS confirmation (docs/design.md, "Completion and segmentation"), where the variant requires it: a voxel is
    // confirmed when a PS echo (the end point of Eq. 11) fell within this many
    // voxels of it (Chebyshev distance). A ray that merely crosses a voxel is
    // evidence of free space, not of an object. Negative: any PS ray crossing or
    // ending in the voxel confirms it (the rule as the design first wrote it).
    int ps_echo_radius = 1;
    // Echoes a voxel must hold to confirm its neighbourhood: at least
    // ps_echo_min_count, and at least ps_echo_min_fraction of the 90th
    // percentile of the echo counts of this map's echo voxels (how many echoes
    // a well-seen surface collects here: it scales with ping density and head
    // speed, so the rule does not assume one). Fraction 0: the count alone.
    int ps_echo_min_count = 2;
    double ps_echo_min_fraction = 0.3;
    // The percentile is taken over the voxels standing above the seabed
    // baseline by more than min_object_height (the map's objects), when any
    // hold echoes: scatter is a share of what the objects collect, not of the
    // seabed, which every ping sweeps. False: over every echo voxel.
    bool ps_echo_reference_above_seabed = true;
    // Where the FLS voted, a PS echo confirms only next to an FLS vote the
    // seabed cannot explain (VoxelMap::flsAboveSeabedVotes within ps_echo_radius).
    // The PS places each echo on every bearing of its fan (Eq. 11), so an object
    // beside the track leaves as many echoes on its mirror across the track; only
    // the FLS, which knows bearing, saw something stand above the seabed on one
    // side (docs/algorithm.md, "The PS's mirror image"). Voxels the FLS never
    // voted, and maps with no above-seabed count at all, keep the PS rule alone.
    bool ps_echo_seen_above_seabed = true;
    // A voxel PS rays crossed without one echo ending in it is confirmed only
    // by echoes in its own layer or above it (within ps_echo_radius), not by
    // those of the layer below: the rays that crossed it went on to the surface
    // below, so it is the water above that surface, which the FLS's elevation
    // arcs fill where the PS fan edge barely carves (docs/algorithm.md, "Water
    // the PS crossed above a surface"). False: the whole neighbourhood counts.
    bool ps_crossed_confirmed_from_level_or_above = true;
    [[nodiscard]] std::optional<ConfigIssue> validate() const;  // keys of the `segmentation` block
};

// Survey mode (issue 13): a pool of bounded maps, allocated at start-up, that
// follows the vehicle. A PS detection outside every active map (and away from
// every object already published) anchors a new map in a free slot; a map the
// vehicle has left is frozen, finalised (segmented, its objects published) and
// its slot freed. docs/algorithm.md, "Survey mode".
struct SurveyConfig {
    int max_maps = 4;  // maps allocated at start-up (1: the single-map mapper of the paper)
    // Horizontal distance (m) beyond a map's extent at which the vehicle has left
    // it. Negative: the longer of the FLS and PS maximum ranges, the farthest
    // either sonar can still reach into the map from.
    double release_margin = -1.0;
    int published_capacity = 256;  // bounding boxes of published objects remembered, to refuse duplicates
    // A finalised map stays in its slot (parked) until a new map needs it; a
    // later line that detects an object inside it reopens it, so both lines'
    // views are fused and its objects republished under the same map id.
    // false: the slot is freed at once and a later line over a published
    // object maps nothing (detection_known_object).
    bool reopen_on_revisit = true;
    [[nodiscard]] std::optional<ConfigIssue> validate() const;  // keys of the `survey` block
};

struct MapperConfig {
    FlsGeometry fls;
    PsGeometry ps;
    Mounting fls_mount;
    Mounting ps_mount;
    MapConfig map;
    UpdateConfig update;
    PsSelectionConfig ps_selection;
    DetectorConfig detector;
    SegmentationConfig segmentation;
    SurveyConfig survey;
    int64_t max_nav_gap_us = 500000;  // refuse to interpolate over a NAV gap larger than this
    int nav_buffer_capacity = 4096;   // NAV samples kept for interpolation
    // A NAV more than max_nav_gap_us away from the newest (ahead, or behind: a
    // clock step) starts a new timeline only once this many such samples, each
    // continuous with the one before, confirm it; until then it is a glitch
    // and the old timeline stays (issue 10, findings 3 and 4).
    int nav_timeline_confirm = 3;
    // Per-ping FLS geometry (docs/algorithm.md, "Per-ping FLS geometry"): FLS
    // geometries (range window, beams, aperture, as each frame carries them)
    // whose direction tables are kept, the configured one included and never
    // evicted; the others are replaced least recently used first. All are
    // allocated at start-up. 1: frames of another geometry are refused.
    int fls_max_geometries = 4;  // key fls.max_geometries
    // Every block above, keys in full ("map.nx", "nav.max_gap_us").
    [[nodiscard]] std::optional<ConfigIssue> validate() const;
};

}  // namespace sonarfusion

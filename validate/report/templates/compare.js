/* validate report: truth / technique comparison (wipe slider and toggle) with a linked error map.
   Inlined into the page; no external resources, works from file://. Each [data-compare] set holds
   .cmp-view (truth image below, technique image above, clipped from the left by the slider's
   per cent), buttons [data-show=truth|wipe|technique], an input[type=range] and the error map.
   When data-linked="1" (error map of the images' own pixel size) a crosshair follows the pointer
   over both at the same relative position. */
(function () {
  "use strict";
  function setup(set) {
    var top = set.querySelector("img.cmp-technique");
    var range = set.querySelector("input.cmp-range");
    var state = set.querySelector(".cmp-state");
    var divider = set.querySelector(".cmp-divider");
    function apply(p) {
      p = Math.max(0, Math.min(100, Number(p)));
      top.style.clipPath = "inset(0 0 0 " + p + "%)";
      divider.style.left = p + "%";
      divider.style.display = (p <= 0 || p >= 100) ? "none" : "block";
      range.value = String(p);
      var s = p >= 100 ? "truth" : (p <= 0 ? "technique" : "wipe");
      set.setAttribute("data-state", s);
      state.textContent = s === "truth" ? "showing: truth" : (s === "technique" ? "showing: technique" :
        "left: truth · right: technique");
      Array.prototype.forEach.call(set.querySelectorAll("button[data-show]"), function (b) {
        b.setAttribute("aria-pressed", String(b.getAttribute("data-show") === s));
      });
    }
    range.addEventListener("input", function () { apply(range.value); });
    Array.prototype.forEach.call(set.querySelectorAll("button[data-show]"), function (b) {
      b.addEventListener("click", function () {
        var s = b.getAttribute("data-show");
        apply(s === "truth" ? 100 : (s === "technique" ? 0 : 50));
      });
    });
    if (set.getAttribute("data-linked") === "1") {
      var boxes = set.querySelectorAll(".cmp-linked");
      var move = function (ev) {
        var r = ev.currentTarget.getBoundingClientRect();
        var u = (ev.clientX - r.left) / r.width, v = (ev.clientY - r.top) / r.height;
        Array.prototype.forEach.call(boxes, function (box) {
          var x = box.querySelector(".cmp-xhair");
          x.style.display = "block";
          x.style.left = (100 * u) + "%";
          x.style.top = (100 * v) + "%";
        });
      };
      Array.prototype.forEach.call(boxes, function (box) { box.addEventListener("mousemove", move); });
    }
    apply(range.value);
  }
  Array.prototype.forEach.call(document.querySelectorAll("[data-compare]"), setup);
})();
